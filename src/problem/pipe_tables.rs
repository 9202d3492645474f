//! The API drill-pipe sizes whose nominal weight a driller may type as a pipe body's
//! `linear_weight` by mistake: a drill-pipe table's nominal weight (the tube with its tool
//! joints, e.g. 5 in 19.50 lb/ft) is heavier than the plain-end weight of the tube, which is what
//! `linear_weight` takes. Sizes: API Spec 5DP (drill pipe), outer diameter, nominal weight and
//! inner diameter of the tube, all in inches and lb/ft as the tables give them.

/// One size of API drill pipe: (outer diameter in, nominal weight lb/ft, tube inner diameter in).
pub type NominalSize = (f64, f64, f64);

/// The API drill-pipe sizes (API Spec 5DP).
pub const API_DRILL_PIPE: &[NominalSize] = &[
    (2.375, 6.65, 1.815),
    (2.875, 10.40, 2.151),
    (3.5, 9.50, 2.992),
    (3.5, 13.30, 2.764),
    (3.5, 15.50, 2.602),
    (4.0, 14.00, 3.340),
    (4.5, 16.60, 3.826),
    (4.5, 20.00, 3.640),
    (5.0, 19.50, 4.276),
    (5.0, 25.60, 4.000),
    (5.5, 21.90, 4.778),
    (5.5, 24.70, 4.670),
    (6.625, 25.20, 5.965),
    (6.625, 27.70, 5.901),
];

const INCH: f64 = 0.0254;
/// 1 lb/ft in kg/m.
const LB_PER_FT: f64 = 0.45359237 / 0.3048;

/// The API size whose outer diameter is `outer_radius` (m, to 0.001 in) and whose nominal weight
/// is `weight` (kg/m, to 0.01 lb/ft), if any: a nominal weight typed as a plain-end weight.
pub fn nominal_weight_of(outer_radius: f64, weight: f64) -> Option<NominalSize> {
    API_DRILL_PIPE.iter().copied().find(|&(od, w, _)| {
        (2.0 * outer_radius / INCH - od).abs() < 1e-3 && (weight / LB_PER_FT - w).abs() < 0.01
    })
}

/// The plain-end weight of `size`'s tube in steel of `density` (kg/m³), lb/ft.
pub fn plain_end_weight_lb_per_ft((od, _, id): NominalSize, density: f64) -> f64 {
    let area = std::f64::consts::PI / 4.0 * (od * od - id * id) * INCH * INCH;
    density * area / LB_PER_FT
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_end_weights_are_those_of_the_api_tables() {
        // API 5DP plain-end weights (lb/ft) of three sizes, w = 10.68 (D − t) t, in steel of
        // 490 lb/ft³ (7849 kg/m³, 10.69 (D − t) t): to 0.03 lb/ft, the tables' rounder steel.
        let steel = 490.0 * 0.45359237 / 0.3048f64.powi(3);
        for (size, plain_end) in [
            ((5.0, 19.50, 4.276), 17.93),
            ((5.5, 21.90, 4.778), 19.81),
            ((3.5, 13.30, 2.764), 12.31),
        ] {
            let w = plain_end_weight_lb_per_ft(size, steel);
            assert!((w - plain_end).abs() < 0.03, "{size:?}: {w}");
        }
    }

    #[test]
    fn only_a_nominal_weight_of_the_same_size_matches() {
        let r = 2.5 * INCH;
        assert_eq!(
            nominal_weight_of(r, 19.5 * LB_PER_FT).map(|s| s.2),
            Some(4.276)
        );
        assert_eq!(nominal_weight_of(r, 17.93 * LB_PER_FT), None);
        assert_eq!(nominal_weight_of(2.75 * INCH, 19.5 * LB_PER_FT), None);
    }
}
