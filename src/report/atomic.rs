//! Atomic file writes: a result file is either the old one or the complete new one, never a
//! half-written mix, even if the process dies mid-write or two runs write the same path.
//!
//! The bytes go to a uniquely named temporary file in the destination's own directory (a rename
//! is atomic only within one filesystem), are fsynced, and the temporary file is renamed over the
//! destination. The directory is then fsynced (best effort) so the rename itself survives a crash.

use std::fs::{self, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use serde::Serialize;

/// Distinguishes temporary files of concurrent writes from the same process (threads of a batch).
static TMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Writes `bytes` to `path` atomically, creating missing parent directories; replaces an existing
/// file. On error no temporary file is left behind and `path` is untouched.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    let name = path.file_name().ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{}: not a file path", path.display()),
        )
    })?;
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    fs::create_dir_all(dir)?;

    let tmp = temp_path(dir, &name.to_string_lossy());
    let result = write_then_rename(&tmp, path, bytes);
    if result.is_err() {
        // The temporary file may not exist (open failed) or may already be renamed; either way
        // there is nothing more useful to report than the original error.
        let _ = fs::remove_file(&tmp);
        return result;
    }
    sync_dir(dir);
    Ok(())
}

/// Writes `value` as pretty-printed JSON (with a final newline) to `path` atomically.
pub fn write_json_atomic<T: Serialize + ?Sized>(path: &Path, value: &T) -> io::Result<()> {
    let mut bytes = serde_json::to_vec_pretty(value).map_err(io::Error::from)?;
    bytes.push(b'\n');
    write_atomic(path, &bytes)
}

/// `.{name}.tmp.{pid}.{n}` in `dir`: hidden, and unique per process and per call.
fn temp_path(dir: &Path, name: &str) -> PathBuf {
    let n = TMP_COUNTER.fetch_add(1, Ordering::Relaxed);
    dir.join(format!(".{name}.tmp.{}.{n}", std::process::id()))
}

fn write_then_rename(tmp: &Path, path: &Path, bytes: &[u8]) -> io::Result<()> {
    // create_new: never clobber a file that someone else (a stale run with a reused pid) owns.
    let mut file = OpenOptions::new().write(true).create_new(true).open(tmp)?;
    file.write_all(bytes)?;
    file.sync_all()?;
    drop(file);
    fs::rename(tmp, path)
}

/// Makes the rename durable. Best effort: some filesystems refuse to fsync a directory, and the
/// file's contents are already safe.
fn sync_dir(dir: &Path) {
    #[cfg(unix)]
    if let Ok(d) = fs::File::open(dir) {
        let _ = d.sync_all();
    }
    #[cfg(not(unix))]
    let _ = dir;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entries(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn writes_creates_parents_and_leaves_no_temp_file() {
        let root = tempfile::tempdir().unwrap();
        let path = root.path().join("a/b/result.txt");
        write_atomic(&path, b"hello").unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"hello");
        assert_eq!(entries(&root.path().join("a/b")), vec!["result.txt"]);
    }

    #[test]
    fn replaces_existing_file_and_leaves_no_temp_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.csv");
        fs::write(&path, b"old contents that are longer than the new ones").unwrap();
        write_atomic(&path, b"new").unwrap();
        write_atomic(&path, b"newer").unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"newer");
        assert_eq!(entries(dir.path()), vec!["out.csv"]);
    }

    #[test]
    fn failed_write_leaves_target_and_directory_untouched() {
        let dir = tempfile::tempdir().unwrap();
        // A directory where the file should go: the rename must fail.
        let path = dir.path().join("taken");
        fs::create_dir(&path).unwrap();
        fs::write(path.join("inner"), b"x").unwrap();
        assert!(write_atomic(&path, b"data").is_err());
        assert_eq!(entries(dir.path()), vec!["taken"]);
        assert_eq!(fs::read(path.join("inner")).unwrap(), b"x");
    }

    #[test]
    fn rejects_path_without_file_name() {
        let err = write_atomic(Path::new("/"), b"x").unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::InvalidInput);
    }

    #[test]
    fn temp_names_are_unique_hidden_and_in_the_same_directory() {
        let dir = Path::new("/some/dir");
        let a = temp_path(dir, "f.json");
        let b = temp_path(dir, "f.json");
        assert_ne!(a, b);
        assert_eq!(a.parent(), Some(dir));
        let name = a.file_name().unwrap().to_string_lossy().into_owned();
        assert!(name.starts_with(".f.json.tmp."), "{name}");
        assert!(name.contains(&std::process::id().to_string()), "{name}");
    }

    #[test]
    fn json_is_pretty_and_round_trips() {
        #[derive(Serialize)]
        struct R {
            name: &'static str,
            values: Vec<f64>,
        }
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("r.json");
        let r = R {
            name: "run",
            values: vec![0.1, -2.5e-300],
        };
        write_json_atomic(&path, &r).unwrap();
        let text = fs::read_to_string(&path).unwrap();
        assert!(text.contains("\n  \"name\": \"run\""), "{text}");
        assert!(text.ends_with("}\n"));
        let back: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(back["values"][0].as_f64(), Some(0.1));
        assert_eq!(back["values"][1].as_f64(), Some(-2.5e-300));
        assert_eq!(entries(dir.path()), vec!["r.json"]);
    }
}
