//! numpy's `.npy` format for the one array kind scene files hold: little-endian float64,
//! C order, two dimensions (rows, columns). The reader is strict: any other version, dtype,
//! order, rank or a length that does not match the header is an error naming it.

use crate::support::error::{Error, Result};
use std::io::{Read, Write};
use std::path::Path;

/// The magic string that opens every `.npy` file.
const MAGIC: &[u8] = b"\x93NUMPY";

/// Largest header read (bytes); numpy's own headers are a few hundred.
const MAX_HEADER: usize = 1 << 16;

/// A 2-D float64 array: `rows` x `columns` values, row-major.
#[derive(Debug, Clone, PartialEq)]
pub struct Array2 {
    /// Rows (the first axis).
    pub rows: usize,
    /// Columns (the second axis).
    pub columns: usize,
    /// Values, row-major.
    pub values: Vec<f64>,
}

/// Reads the `.npy` file at `path`: a little-endian float64 C-order 2-D array.
pub fn read(path: &Path) -> Result<Array2> {
    let shown = path.display();
    let cannot = |e: std::io::Error| Error::InvalidInput(format!("cannot read {shown}: {e}"));
    let mut bytes = vec![];
    std::fs::File::open(path)
        .and_then(|mut f| f.read_to_end(&mut bytes))
        .map_err(cannot)?;
    parse(&bytes).map_err(|m| Error::InvalidInput(format!("{shown}: {m}")))
}

/// Parses the bytes of a `.npy` file; the error says what is wrong.
fn parse(bytes: &[u8]) -> std::result::Result<Array2, String> {
    if !bytes.starts_with(MAGIC) || bytes.len() < MAGIC.len() + 2 {
        return Err("not a .npy file (no \\x93NUMPY magic)".into());
    }
    let (major, minor) = (bytes[6], bytes[7]);
    let (len, start) = match major {
        1 if bytes.len() >= 10 => (u16::from_le_bytes([bytes[8], bytes[9]]) as usize, 10),
        2 | 3 if bytes.len() >= 12 => (
            u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]) as usize,
            12,
        ),
        _ => {
            return Err(format!(
                ".npy format version {major}.{minor} is not supported"
            ))
        }
    };
    if len > MAX_HEADER || bytes.len() < start + len {
        return Err(format!("truncated or oversized header ({len} bytes)"));
    }
    let header = std::str::from_utf8(&bytes[start..start + len])
        .map_err(|_| "the header is not text".to_string())?;
    let (descr, fortran, shape) = header_fields(header)?;
    if descr != "<f8" {
        return Err(format!(
            "dtype {descr:?} is not supported: save the heights as little-endian float64 ('<f8'), e.g. np.save(path, np.asarray(h, dtype='<f8'))"
        ));
    }
    if fortran {
        return Err(
            "Fortran-order arrays are not supported: save a C-order array (np.ascontiguousarray)"
                .into(),
        );
    }
    let [rows, columns] = match shape[..] {
        [r, c] => [r, c],
        _ => {
            return Err(format!(
                "a 2-D array (rows, columns) is needed, got shape {shape:?}"
            ))
        }
    };
    if rows == 0 || columns == 0 {
        return Err(format!("the array is empty (shape ({rows}, {columns}))"));
    }
    let data = &bytes[start + len..];
    let expected = rows
        .checked_mul(columns)
        .and_then(|n| n.checked_mul(8))
        .ok_or_else(|| format!("shape ({rows}, {columns}) is too large"))?;
    if data.len() != expected {
        return Err(format!(
            "shape ({rows}, {columns}) needs {expected} bytes of data, the file holds {}",
            data.len()
        ));
    }
    let values = data
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().expect("chunks of 8 bytes")))
        .collect();
    Ok(Array2 {
        rows,
        columns,
        values,
    })
}

/// (descr, fortran_order, shape) of a header dict such as
/// `{'descr': '<f8', 'fortran_order': False, 'shape': (3, 4), }`.
fn header_fields(header: &str) -> std::result::Result<(String, bool, Vec<usize>), String> {
    let bad = || format!("cannot read the header {:?}", header.trim_end());
    let body = header
        .trim_end()
        .strip_prefix('{')
        .and_then(|h| h.strip_suffix('}'))
        .ok_or_else(bad)?;
    let (mut descr, mut fortran, mut shape) = (None, None, None);
    let mut rest = body.trim_start();
    while !rest.is_empty() {
        let (key, after) = quoted(rest).ok_or_else(bad)?;
        let after = after.trim_start().strip_prefix(':').ok_or_else(bad)?;
        let after = after.trim_start();
        rest = match key {
            "descr" => {
                let (value, after) = quoted(after).ok_or_else(bad)?;
                descr = Some(value.to_string());
                after
            }
            "fortran_order" => {
                let (value, after) = if let Some(a) = after.strip_prefix("True") {
                    (true, a)
                } else if let Some(a) = after.strip_prefix("False") {
                    (false, a)
                } else {
                    return Err(bad());
                };
                fortran = Some(value);
                after
            }
            "shape" => {
                let inner = after.strip_prefix('(').ok_or_else(bad)?;
                let close = inner.find(')').ok_or_else(bad)?;
                let dims = inner[..close]
                    .split(',')
                    .map(str::trim)
                    .filter(|d| !d.is_empty())
                    .map(|d| d.parse::<usize>().map_err(|_| bad()))
                    .collect::<std::result::Result<Vec<usize>, String>>()?;
                shape = Some(dims);
                &inner[close + 1..]
            }
            other => return Err(format!("unknown header key {other:?}")),
        };
        rest = rest.trim_start();
        rest = rest.strip_prefix(',').unwrap_or(rest).trim_start();
    }
    match (descr, fortran, shape) {
        (Some(d), Some(f), Some(s)) => Ok((d, f, s)),
        _ => Err(bad()),
    }
}

/// The content of a leading single- or double-quoted string and what follows it.
fn quoted(text: &str) -> Option<(&str, &str)> {
    let quote = text.chars().next().filter(|c| *c == '\'' || *c == '"')?;
    let body = &text[1..];
    let end = body.find(quote)?;
    Some((&body[..end], &body[end + 1..]))
}

/// Writes `values` (`rows` x `columns`, row-major) to `path` as a version 1.0 `.npy` file
/// of little-endian float64 in C order.
pub fn write(path: &Path, rows: usize, columns: usize, values: &[f64]) -> Result<()> {
    let mut header =
        format!("{{'descr': '<f8', 'fortran_order': False, 'shape': ({rows}, {columns}), }}");
    // magic, version, header length, header and its newline fill a multiple of 64 bytes
    let unpadded = MAGIC.len() + 2 + 2 + header.len() + 1;
    header.push_str(&" ".repeat(unpadded.next_multiple_of(64) - unpadded));
    header.push('\n');
    let mut bytes = Vec::with_capacity(MAGIC.len() + 4 + header.len() + 8 * values.len());
    bytes.extend_from_slice(MAGIC);
    bytes.extend_from_slice(&[1, 0]);
    bytes.extend_from_slice(&(header.len() as u16).to_le_bytes());
    bytes.extend_from_slice(header.as_bytes());
    for v in values {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    std::fs::File::create(path)
        .and_then(|mut f| f.write_all(&bytes))
        .map_err(|e| Error::InvalidInput(format!("cannot write {}: {e}", path.display())))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A version 1.0 file laid out as `np.save` lays it out: header padded with spaces to a
    /// multiple of 64 bytes, then the data.
    fn numpy_bytes(descr: &str, fortran: &str, shape: &str, data: &[f64]) -> Vec<u8> {
        let mut header =
            format!("{{'descr': '{descr}', 'fortran_order': {fortran}, 'shape': {shape}, }}");
        while (10 + header.len() + 1) % 64 != 0 {
            header.push(' ');
        }
        header.push('\n');
        let mut b = b"\x93NUMPY\x01\x00".to_vec();
        b.extend_from_slice(&(header.len() as u16).to_le_bytes());
        b.extend_from_slice(header.as_bytes());
        data.iter()
            .for_each(|v| b.extend_from_slice(&v.to_le_bytes()));
        b
    }

    #[test]
    fn reads_a_numpy_array_and_round_trips_its_own() {
        let data = [0.0, 1.0, 2.0, 3.0, 4.0, -5.5e-7];
        let a = parse(&numpy_bytes("<f8", "False", "(2, 3)", &data)).unwrap();
        assert_eq!((a.rows, a.columns), (2, 3));
        assert_eq!(a.values, data);
        let dir = std::env::temp_dir().join(format!("mdrvisc-npy-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("a.npy");
        write(&path, 2, 3, &data).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(bytes, numpy_bytes("<f8", "False", "(2, 3)", &data));
        assert_eq!(read(&path).unwrap(), a);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn refuses_what_it_cannot_read_naming_it() {
        let refused = |bytes: Vec<u8>, word: &str| {
            let e = parse(&bytes).unwrap_err();
            assert!(e.contains(word), "{e}");
        };
        refused(numpy_bytes("<f4", "False", "(2, 3)", &[0.0; 3]), "<f4");
        refused(numpy_bytes(">f8", "False", "(2, 3)", &[0.0; 6]), "float64");
        refused(numpy_bytes("<f8", "True", "(2, 3)", &[0.0; 6]), "Fortran");
        refused(numpy_bytes("<f8", "False", "(6,)", &[0.0; 6]), "2-D");
        refused(numpy_bytes("<f8", "False", "(0, 3)", &[]), "empty");
        refused(numpy_bytes("<f8", "False", "(2, 3)", &[0.0; 5]), "bytes");
        refused(b"PK\x03\x04".to_vec(), "magic");
    }
}
