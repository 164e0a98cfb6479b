//! Scene files (TOML): a scene plus how to solve it, `method` ("bem" or "mdr") and `n`.
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
//!
//! [indenter]
//! type = "paraboloid"     # rod (radius) | paraboloid (c, edge) | cone (slope, edge)
//! c = 1.0                 # | sphere (radius) | profile (r, h, slope, edge, radius)
//! edge = 2.56
//!
//! [medium]
//! type = "viscous"        # elastic (G) | viscous (eta) | kelvinvoigt (G, eta)
//! eta = 1.0               # | maxwell (G, eta) | standardsolid (G_inf, G1, tau1)
//!                         # | prony (G_inf, terms = [[G_k, tau_k], ...])
//! ```

use super::run::{Method, RunSettings};
use super::Scene;
use crate::error::{Error, Result};
use serde::Deserialize;
use std::io::Read;

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
    /// Parses and validates scene-file text; `source` names it in errors. Unknown, missing
    /// and mistyped keys are errors naming the key; a leading byte-order mark is skipped.
    pub fn parse(text: &str, source: &str) -> Result<Self> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let table: toml::Table =
            toml::from_str(text).map_err(|e| Error::InvalidInput(format!("{source}: {e}")))?;
        Self::from_table(table, source)
    }

    /// Parses and validates a scene file's table given as JSON text.
    pub fn parse_json(text: &str, source: &str) -> Result<Self> {
        let table: toml::Table = serde_json::from_str(text)
            .map_err(|e| Error::InvalidInput(format!("{source}: {e}")))?;
        Self::from_table(table, source)
    }

    fn from_table(mut table: toml::Table, source: &str) -> Result<Self> {
        let bad = |e: String| Error::InvalidInput(format!("{source}: {e}"));
        let method = table
            .remove("method")
            .ok_or_else(|| bad("missing key 'method'".into()))?;
        let method = Method::deserialize(method)
            .map_err(|_| bad("key 'method' must be \"bem\" or \"mdr\"".into()))?;
        let n = match table.remove("n") {
            Some(toml::Value::Integer(n)) if n >= 1 => n as usize,
            Some(other) => {
                return Err(bad(format!("key 'n' must be an integer >= 1, got {other}")))
            }
            None => return Err(bad("missing key 'n'".into())),
        };
        let scene: Scene = serde_path_to_error::deserialize(toml::Value::Table(table))
            .map_err(|e| bad(super::keyed(e)))?;
        scene.validate().map_err(|e| bad(e.message()))?;
        let settings = RunSettings::new(method, n);
        settings.validate().map_err(|e| bad(e.message()))?;
        Ok(SceneFile { scene, settings })
    }

    /// Reads and parses the scene file at `path` (at most `MAX_FILE_BYTES`).
    pub fn load(path: &str) -> Result<Self> {
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
        let text = String::from_utf8(bytes)
            .map_err(|_| Error::InvalidInput(format!("{path}: not UTF-8 text")))?;
        Self::parse(&text, path)
    }

    /// The scene file as TOML text.
    pub fn to_toml(&self) -> String {
        to_toml(&self.scene, Some((self.settings.method, self.settings.n)))
    }
}

/// A scene as TOML text, with `method` and `n` first when given.
pub fn to_toml(scene: &Scene, run: Option<(Method, usize)>) -> String {
    let mut table = toml::Table::new();
    if let Some((method, n)) = run {
        table.insert("method".into(), toml::Value::String(method.name().into()));
        table.insert("n".into(), toml::Value::Integer(n as i64));
    }
    let body = toml::Table::try_from(scene).expect("a validated scene serialises to TOML");
    table.extend(body);
    toml::to_string(&table).expect("a TOML table serialises")
}
