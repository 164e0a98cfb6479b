//! A scene in two parts: its model without the bulk arrays (every key of a scene file, as
//! JSON: numbers, strings, short lists) and the arrays (a height map's heights, a tabulated
//! profile's samples, sampled force and depth histories). The bindings build scenes from
//! the parts, so that arrays cross once, as arrays, and a sweep changes a value of the
//! model without reading the arrays again. `Scene::validate` validates the joined scene,
//! as it does a scene read from a file.

use super::scene::keyed;
use super::{HeightMap, HeightMapTable, History, Indenter, Profile, ProfileTable, Scene};
use crate::support::error::{Error, Result};
use serde::de::DeserializeOwned;
use serde_json::{Map, Value};

/// The bulk arrays of a scene, held apart from its model.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SceneArrays {
    /// A height map's heights (m): shape (ny, nx) and the values, row-major.
    pub heights: Option<([usize; 2], Vec<f64>)>,
    /// A tabulated profile's sample radii (m).
    pub r: Option<Vec<f64>>,
    /// A tabulated profile's heights above the tip (m) at `r`.
    pub h: Option<Vec<f64>>,
    /// A tabulated profile's slopes dh/dr at `r`.
    pub slope: Option<Vec<f64>>,
    /// A sampled force history: [t (s), F (N)] pairs.
    pub force: Option<Vec<[f64; 2]>>,
    /// A sampled depth history: [t (s), d (m)] pairs.
    pub depth: Option<Vec<[f64; 2]>>,
}

/// The dotted model keys that hold the arrays of `SceneArrays`, in its order.
pub const ARRAY_KEYS: [&str; 6] = [
    "indenter.heights",
    "indenter.r",
    "indenter.h",
    "indenter.slope",
    "force",
    "depth",
];

impl SceneArrays {
    /// Whether the array of the dotted model key `key` (one of `ARRAY_KEYS`) is held.
    fn holds(&self, key: &str) -> bool {
        match key {
            "indenter.heights" => self.heights.is_some(),
            "indenter.r" => self.r.is_some(),
            "indenter.h" => self.h.is_some(),
            "indenter.slope" => self.slope.is_some(),
            "force" => self.force.is_some(),
            "depth" => self.depth.is_some(),
            _ => false,
        }
    }

    /// Drops the array of the dotted model key `key` (one of `ARRAY_KEYS`).
    fn drop_key(&mut self, key: &str) {
        match key {
            "indenter.heights" => self.heights = None,
            "indenter.r" => self.r = None,
            "indenter.h" => self.h = None,
            "indenter.slope" => self.slope = None,
            "force" => self.force = None,
            "depth" => self.depth = None,
            _ => {}
        }
    }

    /// Every array of `other` in place of this one's.
    fn replace_with(&mut self, other: SceneArrays) {
        let SceneArrays {
            heights,
            r,
            h,
            slope,
            force,
            depth,
        } = other;
        self.heights = heights.or(self.heights.take());
        self.r = r.or(self.r.take());
        self.h = h.or(self.h.take());
        self.slope = slope.or(self.slope.take());
        self.force = force.or(self.force.take());
        self.depth = depth.or(self.depth.take());
    }
}

/// `value` deserialised as a `T`; errors name the dotted key `key` (and the key inside it).
fn read<T: DeserializeOwned>(key: &str, value: Value) -> Result<T> {
    serde_path_to_error::deserialize(value).map_err(|e| {
        let inner = keyed(e);
        let message = match inner.strip_prefix("key '") {
            Some(rest) => format!("key '{key}.{rest}"),
            None => format!("key '{key}': {inner}"),
        };
        Error::InvalidInput(format!("scene: {message}"))
    })
}

/// The value of `key` taken from `table`, deserialised; None when absent.
fn take<T: DeserializeOwned>(table: &mut Map<String, Value>, key: &str) -> Result<Option<T>> {
    table.remove(key).map(|v| read(key, v)).transpose()
}

fn given_twice(key: &str) -> Error {
    Error::InvalidInput(format!(
        "scene: {key} is given twice: in the model and as an array"
    ))
}

/// A force or depth history: the model's value of `key` or the array's samples.
fn history(
    table: &mut Map<String, Value>,
    key: &str,
    samples: Option<Vec<[f64; 2]>>,
) -> Result<Option<History>> {
    match (take(table, key)?, samples) {
        (Some(_), Some(_)) => Err(given_twice(key)),
        (given, None) => Ok(given),
        (None, Some(samples)) => Ok(Some(History::Samples(samples))),
    }
}

/// The indenter of the model's `[indenter]` table with the arrays it takes from `arrays`
/// (heights of a height map; r, h and slope of a tabulated profile).
fn indenter_from_parts(table: Value, arrays: &mut SceneArrays) -> Result<Indenter> {
    let kind = table.get("type").and_then(Value::as_str).map(str::to_owned);
    let indenter = indenter_with_arrays(table, kind.as_deref(), arrays)?;
    if let Some(key) = ARRAY_KEYS[..4].iter().find(|k| arrays.holds(k)) {
        return Err(Error::InvalidInput(format!(
            "scene: an array is given for '{key}', but the indenter ({}) has no such key",
            kind.as_deref().unwrap_or("without a type")
        )));
    }
    Ok(indenter)
}

fn indenter_with_arrays(
    table: Value,
    kind: Option<&str>,
    arrays: &mut SceneArrays,
) -> Result<Indenter> {
    let Value::Object(mut fields) = table else {
        return read("indenter", table);
    };
    match kind {
        Some("heightmap") if arrays.heights.is_some() => {
            if fields.contains_key("heights") {
                return Err(given_twice("indenter.heights"));
            }
            let ([ny, nx], heights) = arrays.heights.take().expect("checked: held");
            fields.remove("type");
            // the table's own heights are the array's: read its other keys
            fields.insert("heights".into(), Value::Array(vec![]));
            let t: HeightMapTable = read("indenter", Value::Object(fields))?;
            let map = HeightMap::new(ny, nx, heights, t.dx, t.periodic)?;
            Ok(Indenter::HeightMap(Box::new(map)))
        }
        Some("profile") if arrays.r.is_some() || arrays.h.is_some() => {
            let (Some(r), Some(h)) = (arrays.r.take(), arrays.h.take()) else {
                return Err(Error::InvalidInput(
                    "scene: a tabulated profile's r and h arrays come together".into(),
                ));
            };
            for key in ["r", "h", "slope"] {
                if fields.contains_key(key) && (key != "slope" || arrays.slope.is_some()) {
                    return Err(given_twice(&format!("indenter.{key}")));
                }
            }
            fields.remove("type");
            // the table's own samples are the arrays': read its other keys
            fields.insert("r".into(), Value::Array(vec![]));
            fields.insert("h".into(), Value::Array(vec![]));
            let mut t: ProfileTable = read("indenter", Value::Object(fields))?;
            t.r = r;
            t.h = h;
            if let Some(slope) = arrays.slope.take() {
                t.slope = Some(slope);
            }
            Ok(Indenter::Profile(Box::new(Profile::try_from(t)?)))
        }
        _ => read("indenter", Value::Object(fields)),
    }
}

/// The JSON text of `value` (a validated scene's part serialises).
fn text<T: serde::Serialize + ?Sized>(value: &T) -> String {
    serde_json::to_string(value).expect("a validated scene serialises")
}

/// The `[indenter]` table without its arrays, as JSON text, its type first.
fn indenter_model(indenter: &Indenter) -> String {
    match indenter {
        Indenter::HeightMap(map) => format!(
            "{{\"type\":\"heightmap\",\"dx\":{},\"periodic\":{}}}",
            text(&map.dx()),
            map.periodic()
        ),
        Indenter::Profile(p) => {
            let t = p.table();
            let mut out = String::from("{\"type\":\"profile\"");
            for (key, value) in [("edge", t.edge), ("radius", t.radius)] {
                if let Some(v) = value {
                    out += &format!(",\"{key}\":{}", text(&v));
                }
            }
            out + "}"
        }
        other => text(other),
    }
}

impl Scene {
    /// Builds and validates a scene from its model without the arrays (JSON, the keys of a
    /// scene file but `method` and `n`) and its `arrays`. A model key that holds an array
    /// (`ARRAY_KEYS`) may be given in the model or as an array, not both; errors name the
    /// key.
    pub fn from_parts(model: Value, mut arrays: SceneArrays) -> Result<Scene> {
        let Value::Object(mut table) = model else {
            return Err(Error::InvalidInput(format!(
                "scene: the model must be a table of keys, got {model}"
            )));
        };
        let indenter = match table.remove("indenter") {
            Some(t) => indenter_from_parts(t, &mut arrays)?,
            None => return Err(Error::InvalidInput("scene: missing key 'indenter'".into())),
        };
        let scene = Scene {
            indenter,
            medium: take(&mut table, "medium")?
                .ok_or_else(|| Error::InvalidInput("scene: missing key 'medium'".into()))?,
            layer: take(&mut table, "layer")?,
            contact: take(&mut table, "contact")?.unwrap_or_default(),
            force: history(&mut table, "force", arrays.force.take())?,
            depth: history(&mut table, "depth", arrays.depth.take())?,
            duration: take(&mut table, "duration")?,
            times: take(&mut table, "times")?,
            outputs: take(&mut table, "outputs")?,
            field_times: take(&mut table, "field_times")?,
            dt: take(&mut table, "dt")?,
        };
        if let Some(key) = table.keys().next() {
            return Err(Error::InvalidInput(format!("scene: unknown key '{key}'")));
        }
        scene.validate()?;
        Ok(scene)
    }

    /// The model without the arrays, as JSON text in the order of a scene file's keys: the
    /// `model` of `from_parts`, with `arrays()` the whole scene.
    pub fn model(&self) -> String {
        let Scene {
            indenter,
            medium,
            layer,
            contact,
            force,
            depth,
            duration,
            times,
            outputs,
            field_times,
            dt,
        } = self;
        let mut keys = vec![
            ("indenter", indenter_model(indenter)),
            ("medium", text(medium)),
        ];
        if let Some(layer) = layer {
            keys.push(("layer", text(layer)));
        }
        if !contact.is_hard() {
            keys.push(("contact", text(contact)));
        }
        for (key, history) in [("force", force), ("depth", depth)] {
            if let Some(History::Constant(v)) = history {
                keys.push((key, text(v)));
            }
        }
        let optional = [
            ("duration", duration.as_ref().map(text)),
            ("times", times.as_ref().map(text)),
            ("outputs", outputs.as_ref().map(text)),
            ("field_times", field_times.as_ref().map(text)),
            ("dt", dt.as_ref().map(text)),
        ];
        keys.extend(optional.into_iter().filter_map(|(k, v)| v.map(|v| (k, v))));
        let body: Vec<String> = keys
            .into_iter()
            .map(|(key, value)| format!("\"{key}\":{value}"))
            .collect();
        format!("{{{}}}", body.join(","))
    }

    /// The arrays of the scene (copies): the `arrays` of `from_parts`.
    pub fn arrays(&self) -> SceneArrays {
        let mut out = SceneArrays::default();
        match &self.indenter {
            Indenter::HeightMap(map) => out.heights = Some((map.shape(), map.heights().to_vec())),
            Indenter::Profile(p) => {
                let t = p.table();
                (out.r, out.h, out.slope) = (Some(t.r.clone()), Some(t.h.clone()), t.slope.clone());
            }
            _ => {}
        }
        for (slot, history) in [(&mut out.force, &self.force), (&mut out.depth, &self.depth)] {
            if let Some(History::Samples(s)) = history {
                *slot = Some(s.clone());
            }
        }
        out
    }

    /// The scene with the values of `changes` ([dotted model key, value], applied in order)
    /// and the arrays of `replace`, validated. A change at a key drops the arrays under it
    /// (a height map's heights given as a list replace its array); a nested key needs its
    /// table to exist.
    pub fn with_values(
        &self,
        changes: Vec<(String, Value)>,
        replace: SceneArrays,
    ) -> Result<Scene> {
        let mut model: Value = serde_json::from_str(&self.model()).expect("the model is JSON");
        let mut arrays = self.arrays();
        for (key, value) in changes {
            let path: Vec<&str> = key.split('.').collect();
            if path.iter().any(|p| p.is_empty()) {
                return Err(Error::InvalidInput(format!(
                    "scene: key '{key}' has an empty part"
                )));
            }
            let (last, head) = path.split_last().expect("split gives one part at least");
            let mut table = &mut model;
            for part in head {
                table = match table.get_mut(*part) {
                    Some(t) if t.is_object() => t,
                    _ => {
                        return Err(Error::InvalidInput(format!(
                            "scene: key '{key}': the scene has no table '{part}'"
                        )))
                    }
                };
            }
            table
                .as_object_mut()
                .expect("checked: a table")
                .insert(last.to_string(), value);
            for array in ARRAY_KEYS {
                if array == key || array.starts_with(&format!("{key}.")) {
                    arrays.drop_key(array);
                }
            }
        }
        arrays.replace_with(replace);
        Scene::from_parts(model, arrays)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::file::SceneFile;

    fn parts_of(scene: &Scene) -> (Value, SceneArrays) {
        (
            serde_json::from_str(&scene.model()).unwrap(),
            scene.arrays(),
        )
    }

    fn scene(text: &str) -> Scene {
        SceneFile::parse(text, "test").unwrap().scene
    }

    const PROFILE: &str = r#"
        method = "mdr"
        n = 101
        force = [[0.0, 0.0], [1.0, 0.5], [2.0, 0.5]]
        duration = 2.0
        outputs = ["depth", "velocity"]
        [indenter]
        type = "profile"
        r = [0.0, 0.5, 1.0, 2.0]
        h = [0.0, 0.25, 1.0, 4.0]
        slope = [0.0, 1.0, 2.0, 4.0]
        edge = 2.0
        [medium]
        type = "standardsolid"
        G_inf = 1.0
        G1 = 2.0
        tau1 = 0.5
    "#;

    /// Every scene comes back from its parts; the model holds no array, and reads like the
    /// scene's JSON without them.
    #[test]
    fn scenes_round_trip_through_their_parts() {
        let map = HeightMap::new(2, 3, vec![0.1, -0.2, 0.3, 0.0, 1.0, -1.0], 0.5, true).unwrap();
        let mut with_map = scene(PROFILE);
        with_map.indenter = Indenter::HeightMap(Box::new(map));
        let mut depth = scene(PROFILE);
        (depth.force, depth.depth) = (None, Some(History::Constant(0.1)));
        for s in [scene(PROFILE), with_map, depth] {
            let (model, arrays) = parts_of(&s);
            assert_eq!(Scene::from_parts(model, arrays).unwrap(), s);
        }
        let s = scene(PROFILE);
        assert_eq!(
            s.model(),
            "{\"indenter\":{\"type\":\"profile\",\"edge\":2.0},\"medium\":{\"type\":\"standardsolid\",\
             \"G_inf\":1.0,\"G1\":2.0,\"tau1\":0.5},\"duration\":2.0,\"outputs\":[\"depth\",\"velocity\"]}"
        );
        let arrays = s.arrays();
        assert_eq!(arrays.force, Some(vec![[0.0, 0.0], [1.0, 0.5], [2.0, 0.5]]));
        assert_eq!(arrays.slope, Some(vec![0.0, 1.0, 2.0, 4.0]));
    }

    /// Arrays in the model's own form (lists) are read as a scene file's; an array given in
    /// both places, or for an indenter without that key, is refused naming it.
    #[test]
    fn an_array_belongs_in_one_place() {
        let s = scene(PROFILE);
        let full: Value = serde_json::from_str(&s.to_json()).unwrap();
        assert_eq!(
            Scene::from_parts(full.clone(), SceneArrays::default()).unwrap(),
            s
        );
        let refused = |model: Value, arrays: SceneArrays, word: &str| {
            let e = Scene::from_parts(model, arrays).unwrap_err().to_string();
            assert!(e.contains(word), "{e}");
        };
        refused(full.clone(), s.arrays(), "twice");
        let (model, mut arrays) = parts_of(&s);
        arrays.heights = Some(([1, 1], vec![0.0]));
        refused(model.clone(), arrays, "indenter.heights");
        let mut arrays = s.arrays();
        arrays.h = None;
        refused(model.clone(), arrays, "come together");
        let mut bad = model.clone();
        bad["medium"]["tau1"] = Value::from("long");
        refused(bad, s.arrays(), "key 'medium'");
        let mut bad = model;
        bad["colour"] = Value::from(1.0);
        refused(bad, s.arrays(), "colour");
    }

    /// A change replaces one value and keeps the arrays; a change at an array's key
    /// replaces the array; the result is validated.
    #[test]
    fn values_change_without_the_arrays_moving() {
        let s = scene(PROFILE);
        let changed = s
            .with_values(
                vec![("medium.tau1".into(), Value::from(4.0))],
                SceneArrays::default(),
            )
            .unwrap();
        let mut expected = s.clone();
        if let crate::model::Medium::StandardSolid { tau1, .. } = &mut expected.medium {
            *tau1 = 4.0;
        }
        assert_eq!(changed, expected);
        let constant = s
            .with_values(
                vec![("force".into(), Value::from(2.0))],
                SceneArrays::default(),
            )
            .unwrap();
        assert_eq!(constant.force, Some(History::Constant(2.0)));
        let replace = SceneArrays {
            h: Some(vec![0.0, 0.5, 2.0, 8.0]),
            ..SceneArrays::default()
        };
        let steeper = s.with_values(vec![], replace).unwrap();
        assert_eq!(steeper.arrays().h, Some(vec![0.0, 0.5, 2.0, 8.0]));
        for (key, value, word) in [
            ("medium.tau1", Value::from(-1.0), "tau1"),
            ("indentor.c", Value::from(1.0), "indentor"),
            ("medium..tau1", Value::from(1.0), "empty"),
        ] {
            let e = s
                .with_values(vec![(key.into(), value)], SceneArrays::default())
                .unwrap_err()
                .to_string();
            assert!(e.contains(word), "{e}");
        }
    }
}
