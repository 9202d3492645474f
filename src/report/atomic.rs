//! Atomic file writes: a result file is either the old one or the complete new one, never a
//! half-written mix, even if the process dies mid-write or two runs write the same path.
//!
//! The bytes go to a uniquely named temporary file (`tempfile::NamedTempFile`, hidden as
//! `.tmpXXXXXX`) in the destination's own directory (a rename is atomic only within one
//! filesystem), are fsynced, and the temporary file is renamed over the destination
//! (`persist`). The directory is then fsynced (best effort) so the rename itself survives a
//! crash. Every error names the path it concerns, e.g.
//! `results/x/solution.json: Permission denied (os error 13)`.

use std::fs;
use std::io::{self, Write};
use std::path::Path;

use serde::Serialize;
use tempfile::NamedTempFile;

/// Writes `bytes` to `path` atomically, creating missing parent directories; replaces an existing
/// file. On error no temporary file is left behind, `path` is untouched and the error names the
/// path (the directory when it cannot be created).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    if path.file_name().is_none() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{}: not a file path", path.display()),
        ));
    }
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    fs::create_dir_all(dir).map_err(|e| at(dir, &e))?;

    let mut tmp = temp_file(dir).map_err(|e| at(path, &e))?;
    // On any error below, dropping `tmp` (or the `PersistError` holding it) deletes the file.
    tmp.as_file_mut()
        .write_all(bytes)
        .and_then(|()| tmp.as_file().sync_all())
        .map_err(|e| at(path, &e))?;
    tmp.persist(path).map_err(|e| at(path, &e.error))?;
    sync_dir(dir);
    Ok(())
}

/// Writes `value` as pretty-printed JSON (with a final newline) to `path` atomically.
pub fn write_json_atomic<T: Serialize + ?Sized>(path: &Path, value: &T) -> io::Result<()> {
    let mut bytes = serde_json::to_vec_pretty(value).map_err(|e| at(path, &io::Error::from(e)))?;
    bytes.push(b'\n');
    write_atomic(path, &bytes)
}

/// A new temporary file in `dir`, with the permissions a plain `File::create` would give
/// (0o666 less the umask): tempfile's own default, 0o600, would make every result private.
pub(super) fn temp_file(dir: &Path) -> io::Result<NamedTempFile> {
    let mut builder = tempfile::Builder::new();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(fs::Permissions::from_mode(0o666));
    }
    builder.tempfile_in(dir)
}

/// `e` with its message prefixed by `path`: "path: message". tempfile appends the temporary
/// file's own path (" at path …") to errors of its creation; the destination is what a user
/// knows, so that suffix is dropped.
pub(super) fn at(path: &Path, e: &io::Error) -> io::Error {
    let message = e.to_string();
    let message = message.split(" at path ").next().unwrap_or(&message);
    io::Error::new(e.kind(), format!("{}: {message}", path.display()))
}

/// Makes the rename durable. Best effort: some filesystems refuse to fsync a directory, and the
/// file's contents are already safe.
pub(super) fn sync_dir(dir: &Path) {
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
        let err = write_atomic(&path, b"data").unwrap_err();
        assert!(err.to_string().contains("taken: "), "{err}");
        assert_eq!(entries(dir.path()), vec!["taken"]);
        assert_eq!(fs::read(path.join("inner")).unwrap(), b"x");
    }

    #[test]
    fn rejects_path_without_file_name() {
        let err = write_atomic(Path::new("/"), b"x").unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::InvalidInput);
    }

    #[test]
    fn temp_file_is_hidden_in_the_destination_directory_with_ordinary_permissions() {
        let dir = tempfile::tempdir().unwrap();
        let tmp = temp_file(dir.path()).unwrap();
        assert_eq!(tmp.path().parent(), Some(dir.path()));
        let name = tmp
            .path()
            .file_name()
            .unwrap()
            .to_string_lossy()
            .into_owned();
        assert!(name.starts_with('.'), "{name}");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let plain = dir.path().join("plain");
            fs::File::create(&plain).unwrap();
            let mode = |p: &Path| fs::metadata(p).unwrap().permissions().mode() & 0o777;
            assert_eq!(mode(tmp.path()), mode(&plain));
            write_atomic(&dir.path().join("written"), b"x").unwrap();
            assert_eq!(mode(&dir.path().join("written")), mode(&plain));
        }
        drop(tmp);
        assert_eq!(entries(dir.path()), vec!["plain", "written"]);
    }

    #[test]
    fn errors_name_the_path_and_leave_no_temp_file() {
        let dir = tempfile::tempdir().unwrap();
        // The parent is a file: the directory cannot be created, and the error names it.
        let file = dir.path().join("file");
        fs::write(&file, b"x").unwrap();
        let err = write_atomic(&file.join("sub/out.json"), b"data").unwrap_err();
        let text = err.to_string();
        assert!(
            text.starts_with(&format!("{}: ", file.join("sub").display())),
            "{text}"
        );
        assert!(text.contains("os error"), "{text}");

        // A name too long for the filesystem: the rename fails, naming the destination.
        let long = dir.path().join("n".repeat(300));
        let err = write_atomic(&long, b"data").unwrap_err();
        assert_eq!(
            err.to_string(),
            format!("{}: File name too long (os error 36)", long.display())
        );

        // The destination is a directory: the rename fails, naming the destination.
        let taken = dir.path().join("taken");
        fs::create_dir(&taken).unwrap();
        let err = write_atomic(&taken, b"data").unwrap_err();
        assert!(
            err.to_string()
                .starts_with(&format!("{}: ", taken.display())),
            "{err}"
        );
        assert_eq!(entries(dir.path()), vec!["file", "taken"]);

        // Not serialisable as JSON (a map with non-string keys): named too, nothing written.
        let json = dir.path().join("bad.json");
        let bad: std::collections::BTreeMap<(u8, u8), u8> = [((1, 2), 3)].into();
        let err = write_json_atomic(&json, &bad).unwrap_err();
        assert!(
            err.to_string()
                .starts_with(&format!("{}: ", json.display())),
            "{err}"
        );
        assert_eq!(entries(dir.path()), vec!["file", "taken"]);
    }

    #[test]
    fn a_temp_file_that_cannot_be_created_is_reported_at_the_destination() {
        // tempfile names its own temporary path ("… at path …"); the message keeps the
        // destination and the cause only. (A directory that vanished stands in for a
        // read-only one, which root could write to anyway.)
        let dir = tempfile::tempdir().unwrap();
        let gone = dir.path().join("gone");
        let e = temp_file(&gone).unwrap_err();
        assert!(e.to_string().contains(" at path "), "{e}");
        let path = gone.join("solution.json");
        let named = at(&path, &e);
        assert_eq!(
            named.to_string(),
            format!("{}: No such file or directory (os error 2)", path.display())
        );
        assert_eq!(named.kind(), io::ErrorKind::NotFound);
    }

    #[cfg(unix)]
    #[test]
    fn a_read_only_directory_is_named_in_the_error() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let ro = dir.path().join("ro");
        fs::create_dir(&ro).unwrap();
        fs::set_permissions(&ro, fs::Permissions::from_mode(0o555)).unwrap();
        // A privileged user (root in a container) writes anyway: nothing to check then.
        if fs::write(ro.join("probe"), b"").is_ok() {
            fs::remove_file(ro.join("probe")).unwrap();
            return;
        }
        let path = ro.join("solution.json");
        let err = write_atomic(&path, b"{}").unwrap_err();
        assert_eq!(
            err.to_string(),
            format!("{}: Permission denied (os error 13)", path.display())
        );
        assert_eq!(err.kind(), io::ErrorKind::PermissionDenied);
        fs::set_permissions(&ro, fs::Permissions::from_mode(0o755)).unwrap();
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
