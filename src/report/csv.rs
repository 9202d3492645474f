//! The time history of one run as CSV: one header row, then one row per recorded sample.
//!
//! Every scalar channel of [`TimeSeries`] is a column whose name ends with its SI unit
//! (`t_s`, `bit_velocity_m_s`, `torque_on_bit_N_m`; counts and ratios have none), followed by one
//! column per radial probe, `radial_x{position}m_m` (e.g. `radial_x20m_m` for x = 20 m).
//! Reals are written in the shortest form that parses back to the same f64 bit for bit, by
//! [`zmij`] (Rust's `{:?}` form: `0.1`, `1.0`, `-0.0`, `NaN`, `inf`; an exponent below 10⁻⁵ and
//! from 10¹⁶ on, `2.5e-7`, `1e+16`, where plain notation would spell out hundreds of zeros); about
//! five times faster than `{}` on the 13 million values of a 90 s seed run. The rows are the
//! samples of `t`; a channel shorter than `t` (which the simulator never records) gets empty
//! fields rather than a panic.

use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

use tempfile::NamedTempFile;

use crate::sim::{CHANNELS, Row, Sink, TimeSeries};

use super::atomic::{at, sync_dir, temp_file, write_atomic};

enum Values<'a> {
    Real(&'a [f64]),
    Count32(&'a [u32]),
    Count64(&'a [u64]),
}

impl Values<'_> {
    /// Appends sample `i`, or nothing if the channel is too short.
    fn write(&self, out: &mut String, i: usize) {
        match self {
            Values::Real(v) => v.get(i).map(|&x| write_real(out, x)),
            Values::Count32(v) => v
                .get(i)
                .map(|&x| out.push_str(itoa::Buffer::new().format(x))),
            Values::Count64(v) => v
                .get(i)
                .map(|&x| out.push_str(itoa::Buffer::new().format(x))),
        };
    }
}

/// Appends `x` in its shortest round-trip form (see the module documentation).
fn write_real(out: &mut String, x: f64) {
    out.push_str(zmij::Buffer::new().format(x));
}

/// The columns in file order: header name and values. The real channels come from the one
/// declaration, [`CHANNELS`], with the contact counts after the top-drive loads; then one column
/// per probe.
fn columns(s: &TimeSeries) -> Vec<(String, Values<'_>)> {
    let mut cols: Vec<(String, Values<'_>)> = Vec::with_capacity(CHANNELS.len() + 2);
    for ch in &CHANNELS {
        cols.push((ch.column_name(), Values::Real(ch.values(s))));
        // The contact counts sit after the top-drive loads, as in every file written so far.
        if ch.name == "top_torque" {
            cols.push((
                "nodes_in_contact".to_string(),
                Values::Count32(&s.nodes_in_contact),
            ));
            cols.push((
                "contact_onsets".to_string(),
                Values::Count64(&s.contact_onsets),
            ));
        }
    }
    for (k, x) in s.probe_positions.iter().enumerate() {
        let r = s.probe_radial.get(k).map_or(&[][..], Vec::as_slice);
        cols.push((probe_column_name(*x), Values::Real(r)));
    }
    cols
}

/// `radial_x{position}m_m`: radial displacement (m) at the probe at x = `position` m (the
/// position as [`probe_label`] writes it).
pub fn probe_column_name(position: f64) -> String {
    format!("radial_x{}m_m", probe_label(position))
}

/// A probe position in m for names, to the millimetre without trailing zeros: `"20"`, `"12.5"`,
/// `"914.4"` for "3000 ft" (whose double prints as 914.4000000000001; issue 33 item 8).
pub fn probe_label(position: f64) -> String {
    let s = format!("{position:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// The whole series as CSV text (header row, then one row per sample, `\n` line ends).
pub fn timeseries_csv(series: &TimeSeries) -> String {
    let cols = columns(series);
    let rows = series.len();
    // ~20 characters per value is typical of full-precision f64.
    let mut out = String::with_capacity((rows + 1) * cols.len() * 20);
    for (j, (name, _)) in cols.iter().enumerate() {
        if j > 0 {
            out.push(',');
        }
        out.push_str(name);
    }
    out.push('\n');
    for i in 0..rows {
        for (j, (_, values)) in cols.iter().enumerate() {
            if j > 0 {
                out.push(',');
            }
            values.write(&mut out, i);
        }
        out.push('\n');
    }
    out
}

/// The CSV header line (without its line end) of a run with probes at `probes` (m).
fn header(probes: &[f64]) -> String {
    columns(&TimeSeries {
        probe_positions: probes.to_vec(),
        ..TimeSeries::default()
    })
    .into_iter()
    .map(|(name, _)| name)
    .collect::<Vec<_>>()
    .join(",")
}

/// `timeseries.csv` written while the run goes: a [`Sink`] that formats each row it is given
/// into a reused line buffer and writes it through a buffered writer to a temporary file in the
/// destination's directory; [`CsvStream::finish`] flushes, fsyncs and renames it over the
/// destination (see [`super::atomic`]), so a run that dies leaves no half file under the final
/// name. The first I/O error stops the run (the sink returns `false`) and is returned by
/// `finish`, naming the destination path. The rows and the header are those of
/// [`timeseries_csv`], byte for byte.
pub struct CsvStream {
    path: PathBuf,
    dir: PathBuf,
    file: Option<io::BufWriter<NamedTempFile>>,
    line: String,
    error: Option<io::Error>,
}

impl CsvStream {
    /// Create the temporary file for `path` (creating missing directories) and write the header
    /// of a run with probes at `probes` (m).
    pub fn create(path: &Path, probes: &[f64]) -> io::Result<Self> {
        let dir = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        fs::create_dir_all(&dir).map_err(|e| at(&dir, &e))?;
        let tmp = temp_file(&dir).map_err(|e| at(path, &e))?;
        let mut stream = CsvStream {
            path: path.to_path_buf(),
            dir,
            file: Some(io::BufWriter::with_capacity(1 << 20, tmp)),
            line: String::with_capacity(1024),
            error: None,
        };
        stream.line = header(probes);
        stream.line.push('\n');
        stream.write_line();
        match stream.error.take() {
            Some(e) => Err(e),
            None => Ok(stream),
        }
    }

    fn write_line(&mut self) {
        if let Some(f) = &mut self.file
            && let Err(e) = f.write_all(self.line.as_bytes())
        {
            self.error = Some(at(&self.path, &e));
            self.file = None; // dropping the temporary file deletes it
        }
    }

    /// Flush, fsync and rename the file over the destination; the first error of the run, if
    /// any (the temporary file is then removed and the destination untouched).
    pub fn finish(self) -> io::Result<()> {
        if let Some(e) = self.error {
            return Err(e);
        }
        let Some(writer) = self.file else {
            return Ok(());
        };
        let tmp = writer.into_inner().map_err(|e| at(&self.path, e.error()))?;
        tmp.as_file().sync_all().map_err(|e| at(&self.path, &e))?;
        tmp.persist(&self.path)
            .map_err(|e| at(&self.path, &e.error))?;
        sync_dir(&self.dir);
        Ok(())
    }
}

impl Sink for CsvStream {
    fn record(&mut self, row: &Row<'_>) -> bool {
        if self.error.is_some() {
            return false;
        }
        self.line.clear();
        for (k, &v) in row.values.iter().enumerate() {
            if k > 0 {
                self.line.push(',');
            }
            write_real(&mut self.line, v);
            // The contact counts sit after the top-drive loads (see `columns`).
            if CHANNELS[k].name == "top_torque" {
                self.line.push(',');
                self.line
                    .push_str(itoa::Buffer::new().format(row.nodes_in_contact));
                self.line.push(',');
                self.line
                    .push_str(itoa::Buffer::new().format(row.contact_onsets));
            }
        }
        for &r in row.probe_radial {
            self.line.push(',');
            write_real(&mut self.line, r);
        }
        self.line.push('\n');
        self.write_line();
        self.error.is_none()
    }
}

/// Writes [`timeseries_csv`] to `path` atomically.
pub fn write_timeseries_csv(path: &Path, series: &TimeSeries) -> io::Result<()> {
    write_atomic(path, timeseries_csv(series).as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three samples with awkward values: non-terminating binary fractions, extremes, −0, NaN.
    fn small_series() -> TimeSeries {
        let v = |a: f64, b: f64, c: f64| vec![a, b, c];
        TimeSeries {
            t: v(0.0, 1e-7, 0.1 + 0.2),
            bit_displacement: v(0.0, 1.0 / 3.0, -2.2250738585072014e-308),
            bit_velocity: v(f64::MIN_POSITIVE / 4.0, f64::MAX, -0.0),
            bit_rotation: v(std::f64::consts::PI, 1e300, -1e-300),
            bit_angular_velocity: v(f64::NAN, f64::INFINITY, f64::NEG_INFINITY),
            weight_on_bit: v(0.0, 12345.678901234567, 9.87e-5),
            torque_on_bit: v(1.0, 2.0, 3.0),
            top_force: v(-1.5, 2.5, -3.5),
            top_torque: v(0.7, 0.8, 0.9),
            probe_positions: vec![20.0, 12.5],
            probe_radial: vec![v(1e-3, 2e-3, 3.3e-3), v(0.1, 0.2, 0.3)],
            nodes_in_contact: vec![0, 3, u32::MAX],
            contact_onsets: vec![0, 7, u64::MAX],
            wall_force_total: v(4.0, 5.0, 6.0),
            wall_force_max: v(7.0, 8.0, 9.0),
            max_radial_over_gap: v(0.5, 1.0000000000000002, 0.25),
            kinetic_energy: v(1.1, 2.2, 3.3),
            potential_energy: v(4.4, 5.5, 6.6),
            work_top: v(7.7, 8.8, 9.9),
            work_bit: v(-1.0, -2.0, -3.0),
            dissipated: v(0.01, 0.02, 0.03),
            block_speed: v(0.001, 0.002, -0.0),
        }
    }

    fn header(csv: &str) -> Vec<&str> {
        csv.lines().next().unwrap().split(',').collect()
    }

    #[test]
    fn header_names_every_column_with_units() {
        let csv = timeseries_csv(&small_series());
        assert_eq!(
            header(&csv),
            [
                "t_s",
                "bit_displacement_m",
                "bit_velocity_m_s",
                "bit_rotation_rad",
                "bit_angular_velocity_rad_s",
                "weight_on_bit_N",
                "torque_on_bit_N_m",
                "top_force_N",
                "top_torque_N_m",
                "nodes_in_contact",
                "contact_onsets",
                "wall_force_total_N",
                "wall_force_max_N",
                "max_radial_over_gap",
                "kinetic_energy_J",
                "potential_energy_J",
                "work_top_J",
                "work_bit_J",
                "dissipated_J",
                "block_speed_m_s",
                "radial_x20m_m",
                "radial_x12.5m_m",
            ]
        );
    }

    /// Guards against a channel added to `TimeSeries` but forgotten here: every serialized field
    /// except the probe data must be a column, named as the field plus an optional unit suffix.
    #[test]
    fn every_scalar_channel_of_timeseries_is_a_column() {
        let s = small_series();
        let csv = timeseries_csv(&s);
        let cols = header(&csv);
        let json = serde_json::to_value(&s).unwrap();
        let fields = json.as_object().unwrap();
        let scalar: Vec<&String> = fields.keys().filter(|k| !k.starts_with("probe_")).collect();
        assert_eq!(scalar.len() + s.probe_positions.len(), cols.len());
        for key in scalar {
            let found = cols.iter().any(|c| {
                *c == key
                    || c.strip_prefix(key.as_str())
                        .is_some_and(|u| u.starts_with('_'))
            });
            assert!(found, "field {key} has no column in {cols:?}");
        }
    }

    #[test]
    fn rows_parse_back_bit_for_bit() {
        let s = small_series();
        let csv = timeseries_csv(&s);
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines.len(), 1 + s.len());
        let cols = header(&csv);
        let col = |name: &str| cols.iter().position(|c| *c == name).unwrap();
        for (i, line) in lines[1..].iter().enumerate() {
            let fields: Vec<&str> = line.split(',').collect();
            assert_eq!(fields.len(), cols.len());
            let real = |name: &str| fields[col(name)].parse::<f64>().unwrap().to_bits();
            assert_eq!(real("t_s"), s.t[i].to_bits());
            assert_eq!(real("bit_displacement_m"), s.bit_displacement[i].to_bits());
            assert_eq!(real("bit_velocity_m_s"), s.bit_velocity[i].to_bits());
            assert_eq!(real("bit_rotation_rad"), s.bit_rotation[i].to_bits());
            let w = fields[col("bit_angular_velocity_rad_s")]
                .parse::<f64>()
                .unwrap();
            let w0 = s.bit_angular_velocity[i];
            assert!(
                w.to_bits() == w0.to_bits() || (w.is_nan() && w0.is_nan()),
                "{w} vs {w0}"
            );
            assert_eq!(real("weight_on_bit_N"), s.weight_on_bit[i].to_bits());
            assert_eq!(
                real("max_radial_over_gap"),
                s.max_radial_over_gap[i].to_bits()
            );
            assert_eq!(real("work_bit_J"), s.work_bit[i].to_bits());
            assert_eq!(real("radial_x20m_m"), s.probe_radial[0][i].to_bits());
            assert_eq!(real("radial_x12.5m_m"), s.probe_radial[1][i].to_bits());
            let n: u32 = fields[col("nodes_in_contact")].parse().unwrap();
            assert_eq!(n, s.nodes_in_contact[i]);
            let m: u64 = fields[col("contact_onsets")].parse().unwrap();
            assert_eq!(m, s.contact_onsets[i]);
        }
    }

    #[test]
    fn extreme_magnitudes_use_exponents_and_ordinary_ones_do_not() {
        let mut out = String::new();
        for x in [
            1e-300,
            -2.5e-7,
            f64::MAX,
            1e16,
            1e-5,
            0.1,
            12345.678901234567,
            -0.0,
        ] {
            out.clear();
            write_real(&mut out, x);
            assert!(out.len() <= 24, "{x}: {out}");
            assert_eq!(out.parse::<f64>().unwrap().to_bits(), x.to_bits(), "{out}");
        }
        let text = |x: f64| {
            let mut s = String::new();
            write_real(&mut s, x);
            s
        };
        assert_eq!(text(1e-300), "1e-300");
        assert_eq!(text(-2.5e-7), "-2.5e-7");
        assert_eq!(text(1e16), "1e+16");
        assert_eq!(text(1e15), "1000000000000000.0");
        assert_eq!(text(1e-5), "0.00001");
        assert_eq!(text(12345.678901234567), "12345.678901234567");
        assert_eq!(text(-0.0), "-0.0");
        assert_eq!(text(3.0), "3.0");
        assert_eq!(text(f64::NEG_INFINITY), "-inf");
    }

    #[test]
    fn short_channel_gives_empty_fields_not_a_panic() {
        let mut s = small_series();
        s.top_force.truncate(1);
        s.probe_radial.pop();
        let csv = timeseries_csv(&s);
        let cols = header(&csv);
        let last_row: Vec<&str> = csv.lines().last().unwrap().split(',').collect();
        assert_eq!(last_row.len(), cols.len());
        let at = |name: &str| last_row[cols.iter().position(|c| *c == name).unwrap()];
        assert_eq!(at("top_force_N"), "");
        assert_eq!(at("radial_x12.5m_m"), "");
        assert_eq!(at("radial_x20m_m"), "0.0033");
    }

    #[test]
    fn empty_series_is_header_only() {
        let csv = timeseries_csv(&TimeSeries::default());
        assert_eq!(csv.lines().count(), 1);
        assert!(csv.starts_with("t_s,bit_displacement_m,"));
        assert!(csv.ends_with("block_speed_m_s\n"));
    }

    #[test]
    fn write_produces_the_same_text_on_disk() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("run/series.csv");
        let s = small_series();
        write_timeseries_csv(&path, &s).unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), timeseries_csv(&s));
    }

    #[test]
    fn the_stream_writes_the_in_memory_text_and_only_at_finish() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("run/series.csv");
        let s = small_series();
        let mut stream = CsvStream::create(&path, &s.probe_positions).unwrap();
        let mut probes = vec![0.0; s.probe_radial.len()];
        for i in 0..s.len() {
            assert!(stream.record(&s.row(i, &mut probes)));
        }
        // Nothing under the final name before the end (a crash leaves no half file).
        assert!(!path.exists());
        stream.finish().unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), timeseries_csv(&s));
        let names: Vec<_> = std::fs::read_dir(dir.path().join("run")).unwrap().collect();
        assert_eq!(names.len(), 1, "no temporary file left");
    }

    #[test]
    fn a_stream_dropped_unfinished_leaves_nothing_and_errors_name_the_path() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("series.csv");
        drop(CsvStream::create(&path, &[]).unwrap());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
        // A file where the directory should be.
        std::fs::write(dir.path().join("f"), b"").unwrap();
        let bad = dir.path().join("f/series.csv");
        let e = CsvStream::create(&bad, &[]).err().unwrap();
        assert!(
            e.to_string()
                .contains(&dir.path().join("f").display().to_string()),
            "{e}"
        );
    }

    #[test]
    fn probe_labels_are_rounded_to_the_millimetre() {
        assert_eq!(probe_label(20.0), "20");
        assert_eq!(probe_label(12.5), "12.5");
        assert_eq!(probe_label(3000.0 * 0.3048), "914.4");
        assert_eq!(probe_label(0.0), "0");
        assert_eq!(probe_column_name(3000.0 * 0.3048), "radial_x914.4m_m");
    }
}
