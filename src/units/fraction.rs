//! Sizes as drillers write them: a whole number and a fraction, `"8 1/2 in"`, `"8-1/2 in"`,
//! `"2 13/16 in"`, `"8½ in"`, `"6 ⅝ in"`, or a fraction alone, `"3/4 in"`, `"½ in"` (API and
//! vendor tables give pipe and bit sizes so). Read before the plain number of
//! [`super::Dimension::parse`]; anything else is left to it.

/// The vulgar fractions of the tables, with their values.
const VULGAR: [(char, f64); 9] = [
    ('½', 0.5),
    ('¼', 0.25),
    ('¾', 0.75),
    ('⅛', 0.125),
    ('⅜', 0.375),
    ('⅝', 0.625),
    ('⅞', 0.875),
    ('⅓', 1.0 / 3.0),
    ('⅔', 2.0 / 3.0),
];

/// The value of a leading mixed number or fraction of `text` (trimmed) and the rest (the unit,
/// untrimmed), or `None` when `text` does not start with one: `"8 1/2 in"` → (8.5, `" in"`).
/// The fraction follows the whole number after spaces or a hyphen, or directly when it is a
/// vulgar one (`"8½"`); a fraction is proper (numerator below denominator, whole numbers), and
/// what follows it is the end, a space or a letter (so `"5 m/h"`, `"0.03 1/s"` and `"81/2 in"`
/// are no fractions and are read, or refused, as before).
pub(super) fn leading_fraction(text: &str) -> Option<(f64, &str)> {
    let (sign, body) = match text.strip_prefix('-') {
        Some(rest) => (-1.0, rest),
        None => (1.0, text.strip_prefix('+').unwrap_or(text)),
    };
    // A fraction alone: "3/4 in", "½ in".
    if let Some((value, rest)) = fraction(body) {
        return Some((sign * value, rest));
    }
    let whole_len = body
        .find(|c: char| !c.is_ascii_digit())
        .unwrap_or(body.len());
    if whole_len == 0 {
        return None;
    }
    let (whole, rest) = body.split_at(whole_len);
    let candidate = match rest.strip_prefix('-') {
        Some(after_hyphen) => after_hyphen,
        None => rest.trim_start_matches(' '),
    };
    let (part, rest) = fraction(candidate)?;
    let whole: f64 = whole.parse().ok()?;
    Some((sign * (whole + part), rest))
}

/// A fraction at the start of `s`, `n/d` (whole numbers, n < d) followed by the end, a space or
/// a letter, or a vulgar fraction: its value and the rest.
fn fraction(s: &str) -> Option<(f64, &str)> {
    if let Some(c) = s.chars().next()
        && let Some(&(_, value)) = VULGAR.iter().find(|(v, _)| *v == c)
    {
        return Some((value, &s[c.len_utf8()..]));
    }
    let n_len = s.find(|c: char| !c.is_ascii_digit()).unwrap_or(s.len());
    let rest = s[n_len..].strip_prefix('/')?;
    let d_len = rest
        .find(|c: char| !c.is_ascii_digit())
        .unwrap_or(rest.len());
    if n_len == 0 || d_len == 0 {
        return None;
    }
    let after = &rest[d_len..];
    if !(after.is_empty() || after.starts_with(|c: char| c == ' ' || c.is_alphabetic())) {
        return None;
    }
    let n: f64 = s[..n_len].parse().ok()?;
    let d: f64 = rest[..d_len].parse().ok()?;
    // Proper only: the tables write 13/16, never 81/2 (a mistyped 8 1/2, not 40.5).
    (n < d).then_some((n / d, after))
}

#[cfg(test)]
mod tests {
    use super::leading_fraction;

    #[test]
    fn mixed_numbers_and_fractions_as_the_tables_write_them() {
        for (text, value, rest) in [
            ("8 1/2 in", 8.5, " in"),
            ("8-1/2 in", 8.5, " in"),
            ("2 13/16 in", 2.0 + 13.0 / 16.0, " in"),
            ("8½ in", 8.5, " in"),
            ("6 ⅝ in", 6.625, " in"),
            ("3/4 in", 0.75, " in"),
            ("½ in", 0.5, " in"),
            ("-8 1/2 in", -8.5, " in"),
            ("8 1/2in", 8.5, "in"),
            ("2 1/2", 2.5, ""),
        ] {
            let (v, r) = leading_fraction(text).unwrap_or_else(|| panic!("{text}"));
            assert_eq!((v, r), (value, rest), "{text}");
        }
    }

    #[test]
    fn units_with_a_slash_and_plain_numbers_are_no_fractions() {
        for text in [
            "5 m/h",
            "0.03 1/s",
            "30 1/s",
            "1e-5 1/s",
            "81/2 in",
            "8.5 in",
            "8 - 1/2 in",
            "8 1/0 in",
            "8 1/2\" ",
            "in",
            "",
        ] {
            assert_eq!(leading_fraction(text), None, "{text}");
        }
    }
}
