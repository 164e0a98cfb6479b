//! The Rust-only command line: `mdrvisc paper [--scenes DIR] [--json] [--quick]` runs the
//! paper's scenes (the scene files in `examples/paper`), `mdrvisc run SCENE.toml [--json]`
//! runs a scene file. Tables (or one JSON document) go to
//! stdout, progress (a bar with the time left, in a terminal) and errors to stderr; bad input
//! and failed solves exit with status 2. `--help` and `--version` as usual.

use clap::{Parser, Subcommand};
use mdrvisc::model::{RunSettings, Scene, SceneFile};
use mdrvisc::support::monitor::Monitor;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// Rigid indenters on viscous and viscoelastic half-spaces by BEM and MDR.
#[derive(Parser)]
#[command(
    name = "mdrvisc",
    version,
    about,
    after_help = "This Rust binary runs scene files and the paper's scenes only. Fitting \
measured curves (`mdrvisc fit`), sweeps (`mdrvisc sweep`) and the paper's figures come \
with the Python package: pip install mdrvisc, then `mdrvisc --help` or \
`python -m mdrvisc --help`."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run the paper's scenes (rod and paraboloids, BEM and MDR) and print their results.
    Paper {
        /// Folder of the paper's scene files, run in the order of their names.
        #[arg(long, default_value = "examples/paper")]
        scenes: PathBuf,
        /// Print one JSON document instead of tables.
        #[arg(long)]
        json: bool,
        /// The scene files' `[quick]` values (coarse resolutions: BEM rod 50, paraboloids
        /// 65, MDR 4097): seconds.
        #[arg(long)]
        quick: bool,
        /// No progress bar (by default a bar with the time left on stderr, in a terminal).
        #[arg(long)]
        no_progress: bool,
    },
    /// Run one scene file (TOML).
    Run {
        /// The scene file, e.g. examples/rod.toml.
        scene: String,
        /// Print the result as one JSON document instead of a table.
        #[arg(long)]
        json: bool,
        /// No progress bar (by default a bar with the time left on stderr, in a terminal).
        #[arg(long)]
        no_progress: bool,
    },
}

/// Characters of the progress bar.
const BAR_WIDTH: usize = 24;

/// Draws, on one overwritten stderr line, the current stage's bar, count, time elapsed and
/// time left (from the stage's mean rate so far): when enabled (asked for, and stderr is a
/// terminal), at most every 200 ms and at the end of each stage.
struct Progress {
    enabled: bool,
    /// A line is drawn and not yet ended.
    shown: bool,
    /// A stage with a known total is under way.
    active: bool,
    stage: String,
    done: usize,
    total: usize,
    /// The count of the iteration stage under way, if any.
    inner: String,
    start: Instant,
    last: Option<Instant>,
}

/// `seconds` as `12.3 s`, `4 min 05 s` or `2 h 03 min`.
fn duration(seconds: f64) -> String {
    let whole = seconds as u64;
    if seconds < 60.0 {
        format!("{seconds:.1} s")
    } else if seconds < 3600.0 {
        format!("{} min {:02} s", whole / 60, whole % 60)
    } else {
        format!("{} h {:02} min", whole / 3600, whole % 3600 / 60)
    }
}

/// The progress line of `stage` after `elapsed` seconds with `done` of `total` finished.
fn progress_line(stage: &str, done: usize, total: usize, elapsed: f64) -> String {
    let fraction = if total > 0 {
        (done as f64 / total as f64).min(1.0)
    } else {
        1.0
    };
    let filled = (fraction * BAR_WIDTH as f64).round() as usize;
    let left = if done > 0 && done < total {
        let rate = elapsed / done as f64;
        format!(", {} left", duration(rate * (total - done) as f64))
    } else {
        String::new()
    };
    format!(
        "  {stage} [{}{}] {done}/{total} {}{left}",
        "#".repeat(filled),
        "-".repeat(BAR_WIDTH - filled),
        duration(elapsed)
    )
}

impl Monitor for Progress {
    /// A stage named `... iterations` counts towards a limit, not a known total: it is shown
    /// as a count after the current bar, without a time left.
    fn progress(&mut self, stage: &str, done: usize, total: usize) -> mdrvisc::Result<()> {
        if !self.enabled {
            return Ok(());
        }
        if stage.ends_with("iterations") {
            self.inner = format!("{stage} {done}");
            if self.last.is_none_or(|t| t.elapsed().as_millis() >= 200) {
                self.draw();
            }
            return Ok(());
        }
        if !self.active || stage != self.stage || done < self.done {
            if self.active {
                self.close();
            }
            self.stage = stage.to_string();
            self.start = Instant::now();
            self.last = None;
            self.active = true;
        }
        (self.done, self.total) = (done, total);
        self.inner.clear();
        if done >= total || self.last.is_none_or(|t| t.elapsed().as_millis() >= 200) {
            self.draw();
        }
        if done >= total {
            self.close();
        }
        Ok(())
    }
}

impl Progress {
    /// A progress display, drawn only when `wanted` and stderr is a terminal.
    fn new(wanted: bool) -> Self {
        Progress {
            enabled: wanted && std::io::stderr().is_terminal(),
            shown: false,
            active: false,
            stage: String::new(),
            done: 0,
            total: 0,
            inner: String::new(),
            start: Instant::now(),
            last: None,
        }
    }

    /// Overwrites the line with the current bar and iteration count.
    fn draw(&mut self) {
        self.last = Some(Instant::now());
        let mut line = String::new();
        if self.active {
            let elapsed = self.start.elapsed().as_secs_f64();
            line = progress_line(&self.stage, self.done, self.total, elapsed);
        }
        if !self.inner.is_empty() {
            line = format!("{line}  {}", self.inner);
        }
        eprint!("\r{line:78}");
        let _ = std::io::stderr().flush();
        self.shown = true;
    }

    /// Ends the current line.
    fn close(&mut self) {
        if self.shown {
            eprintln!();
            self.shown = false;
        }
        self.active = false;
        self.inner.clear();
    }
}

/// Keys of the paper's scene files beyond a scene file's: the run's label and the values
/// that `--quick` puts over the file's.
const NAME: &str = "name";
const QUICK: &str = "quick";

/// The runs of the paper's scene files in `dir` (every `*.toml`, in the order of their
/// names): each file is a scene file plus `name = "..."`, the run's label, and an optional
/// `[quick]` table of keys that replace the file's when `quick`.
fn paper_runs(dir: &Path, quick: bool) -> Result<Vec<(String, Scene, RunSettings)>, String> {
    let cannot =
        |e: std::io::Error| format!("cannot read the paper's scenes in {}: {e}", dir.display());
    let mut paths = vec![];
    for entry in std::fs::read_dir(dir).map_err(cannot)? {
        let path = entry.map_err(cannot)?.path();
        if path.extension().is_some_and(|e| e == "toml") {
            paths.push(path);
        }
    }
    if paths.is_empty() {
        return Err(format!("no scene files (*.toml) in {}", dir.display()));
    }
    paths.sort();
    paths.iter().map(|path| paper_run(path, quick)).collect()
}

/// One run of `paper_runs`: (name, scene, settings) of the file at `path`.
fn paper_run(path: &Path, quick: bool) -> Result<(String, Scene, RunSettings), String> {
    let source = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read {source}: {e}"))?;
    let mut table: toml::Table = toml::from_str(text.strip_prefix('\u{feff}').unwrap_or(&text))
        .map_err(|e| format!("{source}: {e}"))?;
    let name = match table.remove(NAME) {
        Some(toml::Value::String(name)) => name,
        Some(other) => {
            return Err(format!(
                "{source}: key '{NAME}' must be a string, got {other}"
            ))
        }
        None => return Err(format!("{source}: missing key '{NAME}' (the run's label)")),
    };
    match table.remove(QUICK) {
        Some(toml::Value::Table(values)) if quick => table.extend(values),
        Some(toml::Value::Table(_)) | None => {}
        Some(other) => {
            return Err(format!(
                "{source}: key '{QUICK}' must be a table, got {other}"
            ))
        }
    }
    let base = path.parent().unwrap_or(Path::new(""));
    let file = SceneFile::from_table(table, &source, base).map_err(|e| e.to_string())?;
    Ok((name, file.scene, file.settings))
}

fn run(
    runs: Vec<(String, Scene, RunSettings)>,
    json: bool,
    show_progress: bool,
) -> Result<(), String> {
    let mut documents = vec![];
    for (name, scene, settings) in &runs {
        let mut progress = Progress::new(show_progress);
        let report = mdrvisc::run::run(scene, settings, &mut progress);
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
        Command::Paper {
            scenes,
            json,
            quick,
            no_progress,
        } => run(paper_runs(&scenes, quick)?, json, !no_progress),
        Command::Run {
            scene,
            json,
            no_progress,
        } => {
            let file = SceneFile::load(&scene).map_err(|e| e.to_string())?;
            run(vec![(scene, file.scene, file.settings)], json, !no_progress)
        }
    };
    // On a worker of the pool, the solvers' parallel loops split without waking the main
    // thread.
    let result = mdrvisc::support::pool::run(work).unwrap_or_else(|e| Err(e.to_string()));
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_time_left_is_the_mean_rate_times_the_work_left() {
        // 30 of 120 steps in 9 s: 0.3 s a step, 90 steps left, 27 s.
        let line = progress_line("time steps", 30, 120, 9.0);
        assert!(line.contains("30/120 9.0 s, 27.0 s left"), "{line}");
        assert_eq!(line.matches('#').count(), BAR_WIDTH / 4);
        let finished = progress_line("time steps", 120, 120, 36.0);
        assert!(
            !finished.contains("left") && finished.matches('-').count() == 0,
            "{finished}"
        );
        assert_eq!(duration(125.0), "2 min 05 s");
        assert_eq!(duration(7380.0), "2 h 03 min");
    }
}
