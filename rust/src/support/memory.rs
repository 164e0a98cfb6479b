//! Memory a computation will need, checked against what this process may still use before
//! anything large is allocated, so that a run too big for the machine is a typed error
//! rather than an allocation failure (an abort) or the kernel's out-of-memory kill.

use crate::support::error::{Error, Result};

/// Bytes this process may still allocate: the smaller of the memory the kernel reports
/// available and the room left under the address-space limit; None where neither is known
/// (systems without /proc).
pub fn available() -> Option<f64> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok();
    let free = meminfo
        .as_deref()
        .and_then(|m| kib_field(m, "MemAvailable:"));
    let limits = std::fs::read_to_string("/proc/self/limits").ok();
    let status = std::fs::read_to_string("/proc/self/status").ok();
    let room = match (limits.as_deref().and_then(address_limit), status) {
        (Some(limit), Some(status)) => Some(limit - kib_field(&status, "VmSize:").unwrap_or(0.0)),
        (Some(limit), None) => Some(limit),
        _ => None,
    };
    match (free, room) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// Fails when `bytes` (what `what` would allocate) exceed `available()`; the message names
/// the parameter and both amounts.
pub fn check(what: &str, bytes: f64) -> Result<()> {
    match available() {
        Some(room) if bytes > room => Err(Error::InvalidInput(format!(
            "{what} needs about {} of memory, more than the {} this process has",
            human(bytes),
            human(room.max(0.0))
        ))),
        _ => Ok(()),
    }
}

/// `bytes` as "1.5 GiB".
fn human(bytes: f64) -> String {
    let units = ["B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
    let mut v = bytes;
    let mut k = 0;
    while v >= 1024.0 && k + 1 < units.len() {
        v /= 1024.0;
        k += 1;
    }
    if v.is_finite() {
        format!("{v:.1} {}", units[k])
    } else {
        "more bytes than can be counted".into()
    }
}

/// The value (bytes) of a "Key:   123 kB" line of a /proc file.
fn kib_field(text: &str, key: &str) -> Option<f64> {
    let line = text.lines().find(|l| l.starts_with(key))?;
    let kib: f64 = line[key.len()..].split_whitespace().next()?.parse().ok()?;
    Some(kib * 1024.0)
}

/// The soft address-space limit (bytes) of /proc/self/limits; None when unlimited.
fn address_limit(limits: &str) -> Option<f64> {
    let line = limits
        .lines()
        .find(|l| l.starts_with("Max address space"))?;
    line["Max address space".len()..]
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn proc_fields_are_read() {
        assert_eq!(
            kib_field("MemAvailable:   2048 kB\n", "MemAvailable:"),
            Some(2097152.0)
        );
        let limits = "Limit Soft Hard Units\nMax address space         4294967296           unlimited            bytes\n";
        assert_eq!(address_limit(limits), Some(4294967296.0));
        let unlimited =
            "Max address space         unlimited            unlimited            bytes\n";
        assert_eq!(address_limit(unlimited), None);
        assert_eq!(human(1.5 * 1024.0 * 1024.0 * 1024.0), "1.5 GiB");
        if available().is_some() {
            let e = check("a run", 1e30).unwrap_err().to_string();
            assert!(e.contains("a run needs about"), "{e}");
        }
    }
}
