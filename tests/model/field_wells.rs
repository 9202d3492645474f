//! The shipped field wells built on a published drill string: problems/field/well_a_1km.toml and
//! well_a_3km.toml carry the drill string of Aarsnes & Shor's "Well A" (J. Petroleum Science and
//! Engineering 163, 2018, 712-721; parameters_WellA.m of the authors' public repository
//! Open-Source-Drilling-Community/Aarsnes-and-Shor-Torsional-Model, commit 75afae4). The files
//! are typed as a driller types them (mm, ppg, kft.lbf); this test reads them back against the
//! source's own arrays (m), so that a typo in a transcription cannot pass.

use drillopt::problem::Problem;
use std::path::Path;

/// `LpV`, `ODV`, `IDV` of parameters_WellA.m: the BHA's six rows, m.
const LPV: [f64; 6] = [19.080, 10.240, 57.240, 9.750, 95.400, 38.750];
const ODV: [f64; 6] = [0.150167, 0.206375, 0.150167, 0.206248, 0.150167, 0.222392];
const IDV: [f64; 6] = [0.096799, 0.076200, 0.096799, 0.069850, 0.096799, 0.095964];
/// The drill pipe's diameters (`p.Pro`, `p.Pri` times 2), m.
const DP: [f64; 2] = [0.146529, 0.123024];

#[test]
fn the_well_a_files_carry_the_sources_string() {
    for (file, length) in [("well_a_1km", 1000.0), ("well_a_3km", 3000.0)] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("problems/field")
            .join(format!("{file}.toml"));
        let p = Problem::load(&path).unwrap();
        let s = &p.model.sections;
        assert_eq!(s.len(), 7, "{file}");
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs().max(1.0);
        assert!(close(p.model.length, length), "{file}");
        assert!(close(2.0 * s[0].pipe.outer_radius, DP[0]), "{file}");
        assert!(close(2.0 * s[0].pipe.inner_radius, DP[1]), "{file}");
        // The drill pipe is what the 230.46 m BHA leaves of the lateral.
        let bha: f64 = LPV.iter().sum();
        assert!(close(bha, 230.46));
        assert!(close(s[0].length, length - bha), "{file}: {}", s[0].length);
        for (k, sec) in s[1..].iter().enumerate() {
            assert!(close(sec.length, LPV[k]), "{file} row {k}");
            assert!(close(2.0 * sec.pipe.outer_radius, ODV[k]), "{file} row {k}");
            assert!(close(2.0 * sec.pipe.inner_radius, IDV[k]), "{file} row {k}");
            assert_eq!(sec.pipe.density, 7850.0, "{file} row {k}");
        }
        // The source's set-point.
        assert!(close(
            drillopt::units::to_rpm(p.operating_point.omega),
            60.0
        ));
        // The hole clears the largest tool (the source gives no hole size; the file assumes
        // 9 7/8 in).
        assert!(p.model.borehole_radius > ODV[5] / 2.0);
    }
}
