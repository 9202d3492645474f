//! Append-only evaluation cache on disk (issue 4): no simulation is run twice, and an interrupted
//! optimisation resumes without losing finished work.
//!
//! # File format
//! JSON lines, one record per line, appended in the order evaluations finish:
//!
//! ```text
//! {"key":{"omega_bits":…,"v0_bits":…,"sample":3,"sample_seed":…,"model_hash":…},
//!  "omega":12.566370614359172,"v0":0.005,
//!  "outcome":{"status":"ok","metrics":{"rop":"0.0049871","stick_slip":"NaN"}},
//!  "info":{"wall_time_s":41.2}}
//! ```
//!
//! (one line in the file). The key holds the operating point as f64 bit patterns ([`CacheKey`]);
//! `omega` and `v0` repeat it for readers and are ignored on load. Metric values are strings so
//! that every f64, NaN and ±∞ included, round-trips bit for bit (see [`Outcome`]). When a key
//! appears more than once, the last record wins.
//!
//! # Durability
//! [`EvalCache::insert`] writes the whole line with one `write_all` to a file opened in append
//! mode, then `sync_data`, before it returns: a record that was reported inserted survives a
//! kill or a power cut. A kill during the write can leave a partial last line; on
//! [`open`](EvalCache::open) a last line that does not parse is counted in
//! [`torn`](EvalCache::torn) and cut off the file (truncated), so the next record starts on a
//! fresh line and the file stays valid. A line that does not parse anywhere else is corruption
//! that a kill cannot cause, and `open` refuses the file with its path and line number. If a
//! write fails (disk full) the file is truncated back to its previous length.
//!
//! # Concurrency
//! Inside one process, any number of threads share one [`EvalCache`] (`&self` methods, an
//! internal mutex). Across processes, `open` takes an exclusive advisory lock on the file
//! (`File::try_lock`) and fails with [`CacheError::Locked`] if another process holds it; the
//! lock is released when the cache is dropped. On filesystems without locks the lock is
//! skipped.

mod record;

#[cfg(test)]
mod tests;

pub use crate::hash::stable_hash;
pub use record::{CacheKey, EvalInfo, Outcome};

use record::{RecordIn, RecordOut};
use std::collections::HashMap;
use std::fs::{self, File, OpenOptions, TryLockError};
use std::io::{self, Read, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, PoisonError};

/// Why the cache file could not be opened or written.
#[derive(Debug, thiserror::Error)]
pub enum CacheError {
    #[error("evaluation cache {}: {source}", path.display())]
    Io { path: PathBuf, source: io::Error },
    #[error(
        "evaluation cache {}: line {line} is corrupt ({message}); only a torn last line can be \
         skipped — repair the line or delete the file to start afresh",
        path.display()
    )]
    Corrupt {
        path: PathBuf,
        line: usize,
        message: String,
    },
    #[error(
        "evaluation cache {} is locked by another process; two runs cannot share a cache file",
        path.display()
    )]
    Locked { path: PathBuf },
    #[error("evaluation cache {}: cannot encode a record: {message}", path.display())]
    Encode { path: PathBuf, message: String },
}

/// An outcome in memory, with its optional information.
#[derive(Debug, Clone)]
struct Entry {
    outcome: Outcome,
    info: Option<EvalInfo>,
}

/// State behind the mutex: the file and the map must change together so that the order of the
/// lines matches the order of the map updates (last record wins, on disk and in memory).
struct Inner {
    file: File,
    /// Length of the file, bytes: where the next record starts.
    end: u64,
    entries: HashMap<CacheKey, Entry>,
}

/// The evaluation cache: a map [`CacheKey`] → [`Outcome`] backed by an append-only JSON-lines
/// file (see the module doc).
pub struct EvalCache {
    path: PathBuf,
    inner: Mutex<Inner>,
    hits: AtomicU64,
    misses: AtomicU64,
    loaded: usize,
    torn: usize,
}

impl std::fmt::Debug for EvalCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("EvalCache")
            .field("path", &self.path)
            .field("len", &self.len())
            .field("loaded", &self.loaded)
            .field("torn", &self.torn)
            .field("hits", &self.hits())
            .field("misses", &self.misses())
            .finish()
    }
}

impl EvalCache {
    /// Opens the cache at `path`, creating the file and its parent directories if needed, and
    /// loads its records. A torn last line is dropped (see [`torn`](Self::torn)); a corrupt line
    /// before it is [`CacheError::Corrupt`].
    pub fn open(path: impl AsRef<Path>) -> Result<Self, CacheError> {
        let path = path.as_ref().to_path_buf();
        let io_err = |source| CacheError::Io {
            path: path.clone(),
            source,
        };
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            fs::create_dir_all(dir).map_err(io_err)?;
        }
        let mut file = OpenOptions::new()
            .read(true)
            .append(true)
            .create(true)
            .open(&path)
            .map_err(io_err)?;
        match file.try_lock() {
            Ok(()) => {}
            Err(TryLockError::WouldBlock) => return Err(CacheError::Locked { path }),
            // Locks unsupported here (some network filesystems): go on without one.
            Err(TryLockError::Error(_)) => {}
        }
        let mut bytes = Vec::new();
        file.read_to_end(&mut bytes).map_err(io_err)?;

        let Loaded {
            entries,
            records: loaded,
            torn_at,
        } = parse(&path, &bytes)?;
        let mut end = bytes.len() as u64;
        let mut torn = 0;
        if let Some(start) = torn_at {
            // Cut the torn line off, so that the file holds only whole records again.
            file.set_len(start as u64).map_err(io_err)?;
            end = start as u64;
            torn = 1;
        }
        if end > 0 && bytes[end as usize - 1] != b'\n' {
            // A whole record without its newline (or trailing blanks): end the line before the
            // next record is appended.
            file.write_all(b"\n").map_err(io_err)?;
            end += 1;
        }
        if torn > 0 || end != bytes.len() as u64 {
            file.sync_data().map_err(io_err)?;
        }
        Ok(Self {
            path,
            inner: Mutex::new(Inner { file, end, entries }),
            hits: AtomicU64::new(0),
            misses: AtomicU64::new(0),
            loaded,
            torn,
        })
    }

    /// Whether another process holds the cache file at `path` open (its advisory lock), i.e. a
    /// run is using it now. A missing file is not in use; where locks are unsupported, `false`.
    pub fn in_use(path: impl AsRef<Path>) -> Result<bool, CacheError> {
        let path = path.as_ref();
        let file = match OpenOptions::new().read(true).open(path) {
            Ok(f) => f,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(false),
            Err(source) => {
                return Err(CacheError::Io {
                    path: path.to_path_buf(),
                    source,
                });
            }
        };
        Ok(matches!(file.try_lock(), Err(TryLockError::WouldBlock)))
    }

    /// Records whose key belongs to another model hash: results of other numerics or of another
    /// problem, which this run ignores.
    pub fn other_models(&self, model_hash: u64) -> usize {
        self.lock()
            .entries
            .keys()
            .filter(|k| k.model_hash != model_hash)
            .count()
    }

    /// How many stored keys belong to none of the models `hashes` (None entries are skipped):
    /// [`other_models`](Self::other_models) for a run that uses several models (a
    /// multi-fidelity solve).
    pub fn other_models_than(&self, hashes: &[Option<u64>]) -> usize {
        self.lock()
            .entries
            .keys()
            .filter(|k| !hashes.contains(&Some(k.model_hash)))
            .count()
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Inner> {
        // Inner is updated only after a successful write, so it is consistent even if a thread
        // panicked while holding the lock.
        self.inner.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// The outcome stored for `key`, counting a hit or a miss.
    pub fn get(&self, key: &CacheKey) -> Option<Outcome> {
        let found = self.lock().entries.get(key).map(|e| e.outcome.clone());
        let counter = if found.is_some() {
            &self.hits
        } else {
            &self.misses
        };
        counter.fetch_add(1, Ordering::Relaxed);
        found
    }

    /// The information stored with `key`, if any (does not count as a hit or miss).
    pub fn info(&self, key: &CacheKey) -> Option<EvalInfo> {
        self.lock().entries.get(key).and_then(|e| e.info.clone())
    }

    /// Whether `key` is stored (does not count as a hit or miss).
    pub fn contains(&self, key: &CacheKey) -> bool {
        self.lock().entries.contains_key(key)
    }

    /// Stores `outcome` for `key`: appends one line and syncs it to disk before returning.
    /// Replaces an earlier outcome for the same key.
    pub fn insert(&self, key: CacheKey, outcome: Outcome) -> Result<(), CacheError> {
        self.insert_with_info(key, outcome, None)
    }

    /// [`insert`](Self::insert) with information (wall time, version) stored alongside.
    pub fn insert_with_info(
        &self,
        key: CacheKey,
        outcome: Outcome,
        info: Option<EvalInfo>,
    ) -> Result<(), CacheError> {
        let record = RecordOut {
            key: &key,
            omega: key.omega(),
            v0: key.v0(),
            outcome: &outcome,
            info: info.as_ref(),
        };
        let mut line = serde_json::to_string(&record).map_err(|e| CacheError::Encode {
            path: self.path.clone(),
            message: e.to_string(),
        })?;
        line.push('\n');

        let mut inner = self.lock();
        let written = inner
            .file
            .write_all(line.as_bytes())
            .and_then(|()| inner.file.sync_data());
        if let Err(source) = written {
            // Remove a partial line so that the next record does not continue it.
            let end = inner.end;
            let _ = inner.file.set_len(end);
            return Err(CacheError::Io {
                path: self.path.clone(),
                source,
            });
        }
        inner.end += line.len() as u64;
        inner.entries.insert(key, Entry { outcome, info });
        Ok(())
    }

    /// Number of distinct keys stored.
    pub fn len(&self) -> usize {
        self.lock().entries.len()
    }

    /// Whether no key is stored.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Number of [`get`](Self::get) calls that found their key.
    pub fn hits(&self) -> u64 {
        self.hits.load(Ordering::Relaxed)
    }

    /// Number of [`get`](Self::get) calls that did not.
    pub fn misses(&self) -> u64 {
        self.misses.load(Ordering::Relaxed)
    }

    /// Number of records read from the file when it was opened (repeated keys count each time).
    pub fn loaded(&self) -> usize {
        self.loaded
    }

    /// Number of torn last lines dropped when the file was opened (0 or 1).
    pub fn torn(&self) -> usize {
        self.torn
    }

    /// Path of the cache file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

/// What [`parse`] found in the file.
struct Loaded {
    /// Last record of each key.
    entries: HashMap<CacheKey, Entry>,
    /// Number of records read.
    records: usize,
    /// Byte offset of a torn last line, if there is one.
    torn_at: Option<usize>,
}

/// Reads the records of `bytes`, skipping blank lines.
fn parse(path: &Path, bytes: &[u8]) -> Result<Loaded, CacheError> {
    // (line number from 1, byte offset of its start, its bytes without the newline)
    let mut lines = Vec::new();
    let mut start = 0;
    for (number, line) in bytes.split(|&b| b == b'\n').enumerate() {
        if !line.iter().all(u8::is_ascii_whitespace) {
            lines.push((number + 1, start, line));
        }
        start += line.len() + 1;
    }
    let mut entries = HashMap::new();
    let mut loaded = 0;
    let last = lines.len().saturating_sub(1);
    for (i, &(number, start, line)) in lines.iter().enumerate() {
        let record = std::str::from_utf8(line)
            .map_err(|e| e.to_string())
            .and_then(|text| serde_json::from_str::<RecordIn>(text).map_err(|e| e.to_string()));
        match record {
            Ok(r) => {
                entries.insert(
                    r.key,
                    Entry {
                        outcome: r.outcome,
                        info: r.info,
                    },
                );
                loaded += 1;
            }
            Err(_) if i == last => {
                return Ok(Loaded {
                    entries,
                    records: loaded,
                    torn_at: Some(start),
                });
            }
            Err(message) => {
                return Err(CacheError::Corrupt {
                    path: path.to_path_buf(),
                    line: number,
                    message,
                });
            }
        }
    }
    Ok(Loaded {
        entries,
        records: loaded,
        torn_at: None,
    })
}
