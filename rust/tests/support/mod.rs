//! Running the binary from the integration tests.

use std::process::Command;

/// Runs the `mdrvisc` binary with `args`: exit code, stdout, stderr.
pub fn mdrvisc(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_mdrvisc"))
        .args(args)
        .output()
        .expect("binary runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The numbers of one key of a run's JSON result.
pub fn numbers(result: &serde_json::Value, key: &str) -> Vec<f64> {
    result[key]
        .as_array()
        .unwrap_or_else(|| panic!("{key} is an array"))
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}
