//! The Rust-only command line: `mdrvisc paper [--json] [--quick]` runs the paper's scenes,
//! `mdrvisc run SCENE.toml [--json]` runs a scene file. Tables (or one JSON document) go to
//! stdout, progress and errors to stderr; bad input and failed solves exit with status 2.

use clap::{Parser, Subcommand};
use mdrvisc::monitor::Monitor;
use mdrvisc::paper;
use mdrvisc::scene::{self, RunSettings, Scene, SceneFile};
use std::io::{IsTerminal, Write};
use std::process::ExitCode;
use std::time::Instant;

/// Rigid indenters on viscous and viscoelastic half-spaces by BEM and MDR.
#[derive(Parser)]
#[command(name = "mdrvisc", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run the paper's scenes (rod and paraboloids, BEM and MDR) and print their results.
    Paper {
        /// Print one JSON document instead of tables.
        #[arg(long)]
        json: bool,
        /// Coarse resolutions (BEM rod 50, paraboloids 65, MDR 4097): seconds.
        #[arg(long)]
        quick: bool,
    },
    /// Run one scene file (TOML).
    Run {
        /// The scene file, e.g. examples/rod.toml.
        scene: String,
        /// Print the result as one JSON document instead of a table.
        #[arg(long)]
        json: bool,
    },
}

/// Prints `stage: done/total` on one overwritten stderr line, when stderr is a terminal, at
/// most every 200 ms and at the end of each stage.
struct Progress {
    shown: bool,
    last: Option<Instant>,
}

impl Monitor for Progress {
    fn progress(&mut self, stage: &str, done: usize, total: usize) -> mdrvisc::Result<()> {
        let due = done >= total || self.last.is_none_or(|t| t.elapsed().as_millis() >= 200);
        if due && std::io::stderr().is_terminal() {
            self.last = Some(Instant::now());
            eprint!("\r  {stage}: {done}/{total}{:20}", "");
            let _ = std::io::stderr().flush();
            self.shown = true;
        }
        Ok(())
    }
}

impl Progress {
    fn close(&mut self) {
        if self.shown {
            eprintln!();
            self.shown = false;
        }
    }
}

fn run(runs: Vec<(String, Scene, RunSettings)>, json: bool) -> Result<(), String> {
    let mut documents = vec![];
    let mut progress = Progress {
        shown: false,
        last: None,
    };
    for (name, scene, settings) in &runs {
        let report = scene::run(scene, settings, &mut progress);
        progress.close();
        let report = report.map_err(|e| format!("{name}: {e}"))?;
        if json {
            documents.push(report.document(name, scene));
        } else {
            print!("{}", report.table(name));
        }
    }
    if json {
        println!("{}", serde_json::Value::Array(documents));
    }
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let work = || match cli.command {
        Command::Paper { json, quick } => run(paper::scenes(quick), json),
        Command::Run { scene, json } => {
            let file = SceneFile::load(&scene).map_err(|e| e.to_string())?;
            run(vec![(scene, file.scene, file.settings)], json)
        }
    };
    // On a worker of the pool, the solvers' parallel loops split without waking the main
    // thread.
    let result = mdrvisc::pool::run(work).unwrap_or_else(|e| Err(e.to_string()));
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
