//! A binary built without the `mpi` feature and launched by mpirun would run the whole command on
//! every rank; it refuses instead, saying how to build one that can (issue 15).

#![cfg(not(feature = "mpi"))]

use std::process::Command;

#[test]
fn a_build_without_mpi_refuses_to_run_on_several_ranks() {
    for var in ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE"] {
        let out = Command::new(env!("CARGO_BIN_EXE_drillopt"))
            .args(["modes", "problems/seed_mc2014.toml", "--count", "2"])
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .env(var, "3")
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{var}: ran");
        assert!(
            err.contains("built without MPI") && err.contains("--features mpi"),
            "{err}"
        );
    }
    // One rank (or no mpirun) is an ordinary run.
    let out = Command::new(env!("CARGO_BIN_EXE_drillopt"))
        .args(["modes", "problems/seed_mc2014.toml", "--count", "2"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("OMPI_COMM_WORLD_SIZE", "1")
        .output()
        .unwrap();
    assert!(out.status.success());
}
