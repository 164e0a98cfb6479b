//! The binary: paper scenes, scene files, and clear errors with a non-zero exit.

mod support;

use support::{mdrvisc, numbers};

fn scene_file(name: &str, text: &str) -> String {
    let path = std::env::temp_dir().join(format!("mdrvisc-cli-{}-{name}.toml", std::process::id()));
    std::fs::write(&path, text).expect("temp file");
    path.to_string_lossy().into_owned()
}

const GOOD: &str = r#"
method = "mdr"
n = 4097
force = 1.0
duration = 5.0
[indenter]
type = "paraboloid"
c = 1.0
[medium]
type = "viscous"
eta = 1.0
"#;

#[test]
fn scene_file_runs() {
    let path = scene_file("good", GOOD);
    let (code, out, err) = mdrvisc(&["run", &path, "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).expect("JSON");
    let d = v[0]["result"]["depth"][4].as_f64().unwrap();
    let exact = (3.0f64 * 5.0 * 2f64.sqrt() / 16.0).powf(2.0 / 3.0);
    assert!((d / exact - 1.0).abs() < 1e-5);
}

#[test]
fn bad_scene_files_exit_non_zero_naming_the_problem() {
    let cases = [
        (
            "unknown",
            GOOD.replace("n = 4097", "n = 4097\ncolour = \"red\""),
            "colour",
        ),
        ("missing", GOOD.replace("force = 1.0\n", ""), "force"),
        ("type", GOOD.replace("n = 4097", "n = \"many\""), "n"),
        ("negative", GOOD.replace("eta = 1.0", "eta = -2.0"), "eta"),
        (
            "zero",
            GOOD.replace("duration = 5.0", "duration = 0.0"),
            "duration",
        ),
        ("indenter", GOOD.replace("paraboloid", "teapot"), "teapot"),
    ];
    for (name, text, word) in cases {
        let path = scene_file(name, &text);
        let (code, _, err) = mdrvisc(&["run", &path]);
        assert_eq!(code, 2, "{name}: {err}");
        assert!(err.contains(word), "{name}: {err}");
    }
    let (code, _, err) = mdrvisc(&["run", "/nonexistent/scene.toml"]);
    assert_eq!(code, 2);
    assert!(err.contains("cannot read"));
    let (code, _, err) = mdrvisc(&["frobnicate"]);
    assert_eq!(code, 2);
    assert!(err.contains("Usage"), "{err}");
}

#[test]
fn viscoelastic_scene_with_a_depth_history_loads_unloads_and_separates() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/standard_solid_unloading.toml"
    );
    let (code, out, err) = mdrvisc(&["run", path, "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).expect("JSON");
    let force = numbers(&v[0]["result"], "force");
    // loading raises the force, unloading drops it, and contact is lost before d = 0
    assert!(force[3] > force[2] && force[2] > force[0] && force[0] > 0.0);
    assert!(force[4] < force[3]);
    assert_eq!(force[6], 0.0);
    let both = scene_file(
        "both",
        &GOOD.replace(
            "force = 1.0",
            "force = 1.0\ndepth = [[0.0, 0.0], [1.0, 0.1]]",
        ),
    );
    let (code, _, err) = mdrvisc(&["run", &both]);
    assert_eq!(code, 2);
    assert!(err.contains("only one"), "{err}");
}

/// `paper --scenes DIR` runs every `*.toml` of the folder in the order of the file names,
/// labelled by their `name`, with their `[quick]` values under `--quick`; a folder without
/// scene files and a file without `name` exit with status 2 naming the problem.
#[test]
fn paper_runs_the_scene_files_of_a_folder() {
    let dir = std::env::temp_dir().join(format!("mdrvisc-cli-{}-paper", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp folder");
    let first = format!("name = \"first\"\n{GOOD}");
    let second = format!(
        "name = \"second\"\n{}[quick]\nn = 1025\n",
        GOOD.replace("c = 1.0", "c = 5.0")
    );
    std::fs::write(dir.join("b.toml"), second).expect("temp file");
    std::fs::write(dir.join("a.toml"), first).expect("temp file");
    std::fs::write(dir.join("notes.txt"), "not a scene").expect("temp file");
    let folder = dir.to_string_lossy().into_owned();
    for (quick, n_second) in [(false, 4097), (true, 1025)] {
        let mut args = vec!["paper", "--scenes", &folder, "--json"];
        if quick {
            args.push("--quick");
        }
        let (code, out, err) = mdrvisc(&args);
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(&out).expect("JSON");
        let runs = v.as_array().expect("an array of runs");
        assert_eq!(runs.len(), 2);
        assert_eq!(runs[0]["scene"], "first");
        assert_eq!(runs[1]["scene"], "second");
        assert_eq!(runs[0]["result"]["n"], 4097);
        assert_eq!(runs[1]["result"]["n"], n_second);
        assert_eq!(runs[1]["input"]["indenter"]["c"], 5.0);
    }
    std::fs::write(dir.join("c.toml"), GOOD).expect("temp file");
    let (code, _, err) = mdrvisc(&["paper", "--scenes", &folder]);
    assert_eq!(code, 2);
    assert!(err.contains("c.toml") && err.contains("'name'"), "{err}");
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).expect("temp folder");
    let (code, _, err) = mdrvisc(&["paper", "--scenes", &empty.to_string_lossy()]);
    assert_eq!(code, 2);
    assert!(err.contains("no scene files"), "{err}");
    std::fs::remove_dir_all(&dir).expect("temp folder removed");
}

fn series(path: &str, key: &str) -> Vec<f64> {
    let (code, out, err) = mdrvisc(&["run", path, "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).expect("JSON");
    numbers(&v[0]["result"], key)
}

/// On a viscous half-space the depth depends on the impulse integral F dt alone: a force
/// ramped from 0 to 2 N over 1 s (impulse 1 N s at t = 1) gives the depth that a constant
/// 1 N gives at t = 1 s; then held at 2 N, impulse 3 N s at t = 2 s. The grids are sized
/// from the final impulse, so the two runs differ by the discretisation error (~1e-7).
#[test]
fn force_histories_in_scene_files_follow_the_impulse() {
    let ramp = "force = [[0.0, 0.0], [1.0, 2.0]]";
    for (indenter, method) in [
        ("type = \"paraboloid\"\nc = 1.0", "mdr"),
        ("type = \"rod\"\nradius = 0.5", "mdr"),
        ("type = \"rod\"\nradius = 0.5", "bem"),
    ] {
        let base = GOOD
            .replace("type = \"paraboloid\"\nc = 1.0", indenter)
            .replace("method = \"mdr\"", &format!("method = \"{method}\""))
            .replace(
                "n = 4097",
                if method == "bem" {
                    "n = 40"
                } else {
                    "n = 4097"
                },
            )
            .replace("duration = 5.0", "duration = 2.0\ntimes = [1.0, 2.0]");
        let constant = series(&scene_file("constant", &base), "depth");
        let ramped = series(
            &scene_file("ramp", &base.replace("force = 1.0", ramp)),
            "depth",
        );
        assert!(
            (ramped[0] / constant[0] - 1.0).abs() < 1e-6,
            "{indenter} {method}: {ramped:?} {constant:?}"
        );
        // constant 1 N: impulse 2 N s at t = 2; the ramp: 3 N s
        let (i2, i3) = (2.0f64, 3.0f64);
        let law = if indenter.contains("rod") {
            i3 / i2
        } else {
            (i3 / i2).powf(2.0 / 3.0)
        };
        assert!(
            (ramped[1] / constant[1] / law - 1.0).abs() < 1e-6,
            "{indenter} {method}: {ramped:?} {constant:?}"
        );
    }
    let bad = scene_file("badforce", &GOOD.replace("force = 1.0", "force = \"much\""));
    let (code, _, err) = mdrvisc(&["run", &bad]);
    assert_eq!(code, 2);
    assert!(err.contains("[t, value] pairs"), "{err}");
    let late = scene_file(
        "lateforce",
        &GOOD.replace("force = 1.0", "force = [[0.5, 1.0]]"),
    );
    let (code, _, err) = mdrvisc(&["run", &late]);
    assert_eq!(code, 2);
    assert!(err.contains("t = 0"), "{err}");
}

#[test]
fn version_and_help() {
    let (code, out, _) = mdrvisc(&["--version"]);
    assert_eq!(code, 0);
    assert_eq!(out.trim(), format!("mdrvisc {}", env!("CARGO_PKG_VERSION")));
    let (code, out, _) = mdrvisc(&["--help"]);
    assert_eq!(code, 0);
    assert!(
        out.contains("paper") && out.contains("run") && out.contains("--version"),
        "{out}"
    );
    // it says what it does not cover, and where that is
    assert!(
        out.contains("mdrvisc fit") && out.contains("mdrvisc sweep") && out.contains("pip install"),
        "{out}"
    );
    let (code, out, _) = mdrvisc(&["run", "--help"]);
    assert_eq!(code, 0);
    assert!(
        out.contains("--json") && out.contains("--no-progress"),
        "{out}"
    );
}

#[test]
fn no_progress_gives_the_same_table() {
    let path = scene_file("quiet", GOOD);
    let (code, shown, _) = mdrvisc(&["run", &path]);
    let (quiet_code, quiet, err) = mdrvisc(&["run", "--no-progress", &path]);
    assert_eq!((code, quiet_code), (0, 0), "{err}");
    // the tables differ only in the wall time
    let strip = |s: &str| {
        s.lines()
            .filter(|l| !l.contains("wall="))
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert_eq!(strip(&shown), strip(&quiet));
}
