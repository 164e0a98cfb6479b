//! Scene files (TOML): a scene plus how to solve it, `method` ("bem" or "mdr") and `n`.
//! A height map's heights are a 2-D array inline, or the name of a `.npy` file (little-endian
//! float64, C order, shape (ny, nx)) relative to the scene file; the map fixes the grid, so
//! its `n` may be left out (given, it must be the map's longer side).
//!
//! ```toml
//! method = "bem"          # "bem" or "mdr"
//! n = 257                 # BEM: n x n grid; MDR: elements
//! force = 1.0             # N, constant from t = 0; or [[t, F], ...] (s, N); or depth = ...
//! duration = 5.0          # s (absent for an elastic medium: one static solve)
//! times = [1, 2, 3, 4, 5] # s, optional
//! outputs = ["depth", "contact_length", "pressure"]   # optional
//! field_times = [5.0]     # s, optional
//! dt = 0.01               # s, optional: longest step of the viscoelastic stepping
//! contact = "hard"        # optional: "hard" (default), or adhesion by MDR:
//!                         # { type = "jkr" | "dmt", work_of_adhesion = 0.05 }  (J/m^2)
//!                         # (jkr: stress = 1e6, Pa, optional: its process zone's stress)
//!
//! [indenter]
//! type = "paraboloid"     # rod (radius) | paraboloid (c, edge) | cone (slope, edge)
//! c = 1.0                 # | sphere (radius) | pyramid (half_angle, edge)
//!                         # | profile (r, h, slope, edge, radius)
//! edge = 2.56             # | heightmap (heights = "surface.npy", dx, periodic)
//!
//! [medium]
//! type = "viscous"        # elastic (G) | viscous (eta) | kelvinvoigt (G, eta)
//! eta = 1.0               # | maxwell (G, eta) | standardsolid (G_inf, G1, tau1)
//!                         # | prony (G_inf, terms = [[G_k, tau_k], ...])
//!                         # | powerlaw (G0, beta, t0)
//! nu = 0.5                # Poisson ratio of any medium, -1 < nu <= 0.5, optional
//!
//! [layer]                 # optional: a layer of the medium on a rigid base in place of
//! thickness = 5e-6        # the half-space (m); solved by BEM on a periodic height map
//! base = "bonded"         # "bonded" (default) | "frictionless"
//! ```

use super::settings::{Method, RunSettings};
use super::{Indenter, Scene};
use crate::support::error::{Error, Result};
use crate::support::npy;
use serde::Deserialize;
use std::io::Read;
use std::path::Path;

/// Largest scene file read (bytes): tabulated profiles and histories fit many times over.
pub const MAX_FILE_BYTES: u64 = 64 << 20;

/// A scene file: the scene and the method and resolution it is solved with.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneFile {
    /// The scene.
    pub scene: Scene,
    /// How to solve it.
    pub settings: RunSettings,
}

impl SceneFile {
    /// Parses and validates scene-file text; `source` names it in errors, and files it
    /// names are read relative to the current directory. Unknown, missing and mistyped keys
    /// are errors naming the key; a leading byte-order mark is skipped.
    pub fn parse(text: &str, source: &str) -> Result<Self> {
        Self::parse_in(text, source, Path::new(""))
    }

    /// `parse`, reading the files the scene names relative to `base`.
    fn parse_in(text: &str, source: &str, base: &Path) -> Result<Self> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let table: toml::Table =
            toml::from_str(text).map_err(|e| Error::InvalidInput(format!("{source}: {e}")))?;
        Self::from_table(table, source, base)
    }

    /// Parses and validates a scene file's table given as JSON text (files it names are
    /// read relative to the current directory).
    pub fn parse_json(text: &str, source: &str) -> Result<Self> {
        let table: toml::Table = serde_json::from_str(text)
            .map_err(|e| Error::InvalidInput(format!("{source}: {e}")))?;
        Self::from_table(table, source, Path::new(""))
    }

    /// Validates a scene file's table (as `toml` reads it); `source` names it in errors, and
    /// files it names are read relative to `base`.
    pub fn from_table(mut table: toml::Table, source: &str, base: &Path) -> Result<Self> {
        let bad = |e: String| Error::InvalidInput(format!("{source}: {e}"));
        let method = table
            .remove("method")
            .ok_or_else(|| bad("missing key 'method'".into()))?;
        let method = Method::deserialize(method)
            .map_err(|_| bad("key 'method' must be \"bem\" or \"mdr\"".into()))?;
        let n = match table.remove("n") {
            Some(toml::Value::Integer(n)) if n >= 1 => Some(n as usize),
            Some(other) => {
                return Err(bad(format!("key 'n' must be an integer >= 1, got {other}")))
            }
            None => None,
        };
        let scene = scene_of(table, source, base)?;
        let n = match (n, &scene.indenter) {
            (Some(n), _) => n,
            (None, Indenter::HeightMap(map)) => map.n(),
            (None, _) => return Err(bad("missing key 'n'".into())),
        };
        if let Indenter::HeightMap(map) = &scene.indenter {
            map.check_run(method, n).map_err(|e| bad(e.message()))?;
        }
        let settings = RunSettings::new(method, n);
        settings.validate().map_err(|e| bad(e.message()))?;
        Ok(SceneFile { scene, settings })
    }

    /// Reads and parses the scene file at `path` (at most `MAX_FILE_BYTES`).
    pub fn load(path: &str) -> Result<Self> {
        let text = read(path)?;
        let base = Path::new(path).parent().unwrap_or(Path::new(""));
        Self::parse_in(&text, path, base)
    }

    /// The scene of the scene file at `path`, whose `method` and `n` may be absent (as
    /// `to_toml` writes a scene without them); when `method` is there, the whole file is
    /// checked as `load` does.
    pub fn load_scene(path: &str) -> Result<Scene> {
        let text = read(path)?;
        let base = Path::new(path).parent().unwrap_or(Path::new(""));
        let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
        let mut table: toml::Table =
            toml::from_str(text).map_err(|e| Error::InvalidInput(format!("{path}: {e}")))?;
        if table.contains_key("method") {
            return Self::from_table(table, path, base).map(|file| file.scene);
        }
        match table.remove("n") {
            Some(toml::Value::Integer(n)) if n >= 1 => {}
            Some(other) => {
                return Err(Error::InvalidInput(format!(
                    "{path}: key 'n' must be an integer >= 1, got {other}"
                )))
            }
            None => {}
        }
        scene_of(table, path, base)
    }

    /// The scene file as TOML text (a height map's heights inline).
    pub fn to_toml(&self) -> String {
        to_toml(&self.scene, Some((self.settings.method, self.settings.n)))
    }
}

/// The text of the file at `path`: at most `MAX_FILE_BYTES` bytes of UTF-8.
fn read(path: &str) -> Result<String> {
    let cannot =
        |e: std::io::Error| Error::InvalidInput(format!("cannot read scene file {path}: {e}"));
    let mut bytes = vec![];
    std::fs::File::open(path)
        .and_then(|f| f.take(MAX_FILE_BYTES + 1).read_to_end(&mut bytes))
        .map_err(cannot)?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(Error::InvalidInput(format!(
            "{path}: a scene file is at most {MAX_FILE_BYTES} bytes"
        )));
    }
    String::from_utf8(bytes).map_err(|_| Error::InvalidInput(format!("{path}: not UTF-8 text")))
}

/// The validated scene of a scene file's table without `method` and `n`; `source` names it
/// in errors, and files it names are read relative to `base`.
fn scene_of(mut table: toml::Table, source: &str, base: &Path) -> Result<Scene> {
    let bad = |e: String| Error::InvalidInput(format!("{source}: {e}"));
    read_heights(&mut table, base).map_err(|e| bad(e.message()))?;
    let scene: Scene = serde_path_to_error::deserialize(toml::Value::Table(table))
        .map_err(|e| bad(super::scene::keyed(e)))?;
    scene.validate().map_err(|e| bad(e.message()))?;
    Ok(scene)
}

/// Replaces a height map's `heights` given as a file name by the array of that `.npy`
/// file (relative to `base`), rows of numbers.
fn read_heights(table: &mut toml::Table, base: &Path) -> Result<()> {
    let Some(toml::Value::Table(indenter)) = table.get_mut("indenter") else {
        return Ok(());
    };
    let Some(toml::Value::String(name)) = indenter.get("heights") else {
        return Ok(());
    };
    let array = npy::read(&base.join(name))
        .map_err(|e| Error::InvalidInput(format!("key 'indenter.heights': {}", e.message())))?;
    let rows = array
        .values
        .chunks(array.columns)
        .map(|row| toml::Value::Array(row.iter().map(|&h| toml::Value::Float(h)).collect()))
        .collect();
    indenter.insert("heights".into(), toml::Value::Array(rows));
    Ok(())
}

/// A scene as a TOML table, with `method` and `n` first when given.
fn to_table(scene: &Scene, run: Option<(Method, usize)>) -> toml::Table {
    let mut table = toml::Table::new();
    if let Some((method, n)) = run {
        table.insert("method".into(), toml::Value::String(method.name().into()));
        table.insert("n".into(), toml::Value::Integer(n as i64));
    }
    let body = toml::Table::try_from(scene).expect("a validated scene serialises to TOML");
    table.extend(body);
    table
}

/// A scene as TOML text, with `method` and `n` first when given; a height map's heights
/// inline.
pub fn to_toml(scene: &Scene, run: Option<(Method, usize)>) -> String {
    toml::to_string(&to_table(scene, run)).expect("a TOML table serialises")
}

/// Writes a scene file to `path` (with `method` and `n` first when given) and returns its
/// text; a height map's heights go to a `.npy` file beside it, named after it
/// (`scene.toml`: `scene.npy`), which the file names.
pub fn write(scene: &Scene, run: Option<(Method, usize)>, path: &Path) -> Result<String> {
    let mut table = to_table(scene, run);
    if let Indenter::HeightMap(map) = &scene.indenter {
        let npy_path = path.with_extension("npy");
        if npy_path == path {
            return Err(Error::InvalidInput(format!(
                "{}: a scene file needs its own name, not the .npy of its heights",
                path.display()
            )));
        }
        let name = npy_path
            .file_name()
            .and_then(|n| n.to_str())
            .ok_or_else(|| {
                Error::InvalidInput(format!("cannot name a .npy file beside {}", path.display()))
            })?
            .to_string();
        let [ny, nx] = map.shape();
        npy::write(&npy_path, ny, nx, map.heights())?;
        if let Some(toml::Value::Table(indenter)) = table.get_mut("indenter") {
            indenter.insert("heights".into(), toml::Value::String(name));
        }
    }
    let text = toml::to_string(&table).expect("a TOML table serialises");
    std::fs::write(path, &text)
        .map_err(|e| Error::InvalidInput(format!("cannot write {}: {e}", path.display())))?;
    Ok(text)
}
