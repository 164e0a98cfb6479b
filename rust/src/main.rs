//! The Rust-only command line: `mdrvisc paper [--json] [--quick]` runs the paper's scenes,
//! `mdrvisc run SCENE.toml [--json]` runs a scene file.

use mdrvisc::contact::SolverOptions;
use mdrvisc::monitor::Silent;
use mdrvisc::scenes::{ForceSpec, Indenter, MediumSpec, Method, Report, Scene};
use std::process::ExitCode;

const USAGE: &str =
    "usage: mdrvisc paper [--json] [--quick]\n       mdrvisc run SCENE.toml [--json]";

/// The paper's scenes: the rod (Section 5) and the paraboloids (Section 6).
fn paper_scenes(quick: bool) -> Vec<(String, Scene)> {
    let viscous = MediumSpec::Viscous { eta: 1.0 };
    let (n_rod, n_bem, n_mdr) = if quick {
        (50, 65, 4097)
    } else {
        (200, 257, 66049)
    };
    let mut out = vec![];
    for (method, n) in [(Method::Bem, n_rod), (Method::Mdr, n_mdr)] {
        out.push((
            "rod a=1".to_string(),
            Scene {
                indenter: Indenter::Rod { radius: 1.0 },
                medium: viscous.clone(),
                force: Some(ForceSpec::Constant(1.0)),
                depth: None,
                dt: None,
                outputs: None,
                duration: 1.0,
                method,
                n,
                times: Some(vec![1.0]),
            },
        ));
    }
    for c in [0.05, 0.2, 1.0, 5.0, 20.0] {
        for (method, n) in [(Method::Bem, n_bem), (Method::Mdr, n_mdr)] {
            out.push((
                format!("paraboloid c={c}"),
                Scene {
                    indenter: Indenter::Paraboloid {
                        c,
                        edge: Some(2.56),
                    },
                    medium: viscous.clone(),
                    force: Some(ForceSpec::Constant(1.0)),
                    depth: None,
                    dt: None,
                    outputs: None,
                    duration: 5.0,
                    method,
                    n,
                    times: None,
                },
            ));
        }
    }
    out
}

fn print_table(name: &str, r: &Report) {
    let method = match r.method {
        Method::Bem => "BEM",
        Method::Mdr => "MDR",
    };
    println!(
        "{name} — {method} n={} dx={:.4e} m  iterations={}  residual={:.2e}  wall={:.3} s",
        r.n, r.dx, r.iterations, r.residual, r.wall_time
    );
    if let Some(p0) = r.central_pressure {
        println!("  central pressure p0 = {p0:.6} Pa");
    }
    let (label, last) = match &r.force {
        Some(f) => ("F [N]", f),
        None => ("dd/dt [m/s]", &r.velocity),
    };
    println!(
        "  {:>8} {:>14} {:>14} {:>14}",
        "t [s]", "d [m]", "l [m]", label
    );
    for (i, value) in last.iter().enumerate() {
        println!(
            "  {:>8.3} {:>14.8} {:>14.8} {:>14.8}",
            r.t[i], r.depth[i], r.contact_length[i], value
        );
    }
}

fn run(args: &[String]) -> Result<(), String> {
    let json = args.iter().any(|a| a == "--json");
    let quick = args.iter().any(|a| a == "--quick");
    let positional: Vec<&String> = args.iter().filter(|a| !a.starts_with("--")).collect();
    if let Some(bad) = args
        .iter()
        .find(|a| a.starts_with("--") && *a != "--json" && *a != "--quick")
    {
        return Err(format!("unknown option {bad}\n{USAGE}"));
    }
    let scenes = match positional.as_slice() {
        [cmd] if cmd.as_str() == "paper" => paper_scenes(quick),
        [cmd, path] if cmd.as_str() == "run" => {
            let text =
                std::fs::read_to_string(path).map_err(|e| format!("cannot read {path}: {e}"))?;
            vec![(
                path.to_string(),
                Scene::from_toml(&text).map_err(|e| e.to_string())?,
            )]
        }
        _ => return Err(USAGE.to_string()),
    };
    let opts = SolverOptions::default();
    let mut reports = vec![];
    for (name, scene) in &scenes {
        let r = scene
            .run(&opts, &mut Silent)
            .map_err(|e| format!("{name}: {e}"))?;
        if !json {
            print_table(name, &r);
        }
        reports.push(serde_json::json!({ "scene": name, "input": scene, "result": r }));
    }
    if json {
        println!("{}", serde_json::Value::Array(reports));
    }
    Ok(())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    // On a rayon worker, the solvers' parallel loops split without waking the main thread.
    let (result, ()) = rayon::join(|| run(&args), || ());
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
