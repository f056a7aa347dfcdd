//! CSV files of the observers: create, continue after a checkpoint, and
//! write whole rows only.
//!
//! Rows are built in memory and reach the file only as whole rows: when
//! [`FLUSH_BYTES`] are pending, when [`FLUSH_SECONDS`] have passed since the
//! last write (so a batch user sees rows on disk while a long run goes on),
//! at a checkpoint and at the end. A write that fails part way (a full disk)
//! is cut back to the rows before it, so the file never ends in half a row;
//! a process killed between two writes leaves whole rows too.

use super::mark::Mark;
use super::Row;
use crate::error::{Error, Result};
use std::fs::File;
use std::io::{Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Pending bytes that trigger a write.
pub const FLUSH_BYTES: usize = 1 << 16;

/// Longest time rows stay in memory while a run goes on, s.
pub const FLUSH_SECONDS: u64 = 2;

/// A CSV output file of an observer, opened when the run starts: created
/// with its header ([`CsvFile::create`]) or continued after a checkpoint
/// ([`CsvFile::reopen`]).
pub struct CsvFile {
    /// The file's path.
    pub path: PathBuf,
    file: Option<File>,
    /// Whole rows not yet in the file.
    pending: Vec<u8>,
    /// Bytes in the file, all of them whole rows.
    on_disk: u64,
    /// When the pending rows were last written.
    written_at: Instant,
}

/// The error of a file written before it was opened (a bug, reported, not a panic).
pub(crate) fn not_open(path: &Path) -> Error {
    Error::io(path, std::io::Error::other("written before it was opened"))
}

impl CsvFile {
    /// The file at `path`, not yet opened.
    pub fn at(path: PathBuf) -> Self {
        CsvFile {
            path,
            file: None,
            pending: Vec::new(),
            on_disk: 0,
            written_at: Instant::now(),
        }
    }

    /// Create the file with its header row (written with the first rows).
    pub fn create(&mut self, header: &[&str]) -> Result<()> {
        let f = File::create(&self.path).map_err(|e| Error::io(&self.path, e))?;
        self.file = Some(f);
        self.on_disk = 0;
        self.written_at = Instant::now();
        let mut row = self.row()?;
        for h in header {
            row.text(h);
        }
        row.end();
        Ok(())
    }

    /// Open the file for appending after cutting it to `len` bytes (resume).
    pub fn reopen(&mut self, len: u64) -> Result<()> {
        self.file = Some(reopen_cut(&self.path, len)?);
        self.on_disk = len;
        self.written_at = Instant::now();
        Ok(())
    }

    /// A new row at the end of the pending ones.
    pub fn row(&mut self) -> Result<Row<'_>> {
        if self.file.is_none() {
            return Err(not_open(&self.path));
        }
        Ok(Row::new(&mut self.pending))
    }

    /// The rows of one step are complete: write them out if enough are
    /// pending or if the last write is [`FLUSH_SECONDS`] old (one clock
    /// read per output step, none per simulation step).
    pub fn rows_done(&mut self) -> Result<()> {
        if self.pending.len() >= FLUSH_BYTES
            || self.written_at.elapsed() >= Duration::from_secs(FLUSH_SECONDS)
        {
            self.flush()?;
        }
        Ok(())
    }

    /// Write the pending rows. On failure the file is cut back to the rows
    /// it held before, and the pending rows are dropped: the run stops with
    /// the error, and its file ends in a whole row.
    pub fn flush(&mut self) -> Result<()> {
        self.written_at = Instant::now();
        if self.pending.is_empty() {
            return Ok(());
        }
        let Some(f) = self.file.as_mut() else {
            return Err(not_open(&self.path));
        };
        match f.write_all(&self.pending) {
            Ok(()) => {
                self.on_disk += self.pending.len() as u64;
                self.pending.clear();
                Ok(())
            }
            Err(e) => {
                self.pending.clear();
                let kept = self.on_disk;
                let cut = f
                    .set_len(kept)
                    .and_then(|_| f.seek(SeekFrom::Start(kept)).map(|_| ()));
                let said = match cut {
                    Ok(()) => format!("{e}; the file keeps the whole rows written before it ({kept} bytes)"),
                    Err(c) => format!("{e}; cutting the file back to its last whole row ({kept} bytes) failed too: {c}"),
                };
                Err(Error::io(&self.path, std::io::Error::new(e.kind(), said)))
            }
        }
    }

    /// Write the pending rows and mark the file for a checkpoint.
    pub fn mark(&mut self) -> Result<Mark> {
        self.flush()?;
        Mark::of_file(&self.path, self.on_disk).map_err(|e| Error::io(&self.path, e))
    }

    /// The file name, as checkpoints record it.
    pub fn name(&self) -> String {
        self.path
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
    }
}

impl Drop for CsvFile {
    /// A run that ends by an error elsewhere still writes its whole rows.
    fn drop(&mut self) {
        if self.file.is_some() {
            let _ = self.flush();
        }
    }
}

/// An output file a checkpoint continues, cut to the `len` bytes it
/// recorded and positioned at its end; bad input if it is missing or shorter.
pub(crate) fn reopen_cut(path: &Path, len: u64) -> Result<File> {
    let mut f = std::fs::OpenOptions::new()
        .write(true)
        .open(path)
        .map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => Error::bad(
                path.display().to_string(),
                "--resume",
                format!("the output file the checkpoint continues is missing ({e}); resume from the checkpoint in its own folder"),
            ),
            _ => Error::io(path, e),
        })?;
    let have = f.metadata().map_err(|e| Error::io(path, e))?.len();
    if have < len {
        // set_len would pad with zero bytes: the file is not the one checkpointed.
        return Err(Error::bad(
            path.display().to_string(),
            "--resume",
            format!("is {have} bytes, shorter than the {len} the checkpoint recorded: it was changed after the checkpoint; rerun from the start"),
        ));
    }
    f.set_len(len).map_err(|e| Error::io(path, e))?;
    f.seek(SeekFrom::End(0)).map_err(|e| Error::io(path, e))?;
    Ok(f)
}

/// Write `bytes` as the whole file `path`: to a temporary name beside it,
/// then renamed, so the file is whole or absent after a kill or a full
/// disk (the temporary file is removed on failure).
pub fn write_whole(path: &Path, bytes: &[u8]) -> Result<()> {
    let tmp = temporary(path);
    let written = std::fs::write(&tmp, bytes).and_then(|_| std::fs::rename(&tmp, path));
    written.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        Error::io(path, e)
    })
}

/// The temporary name [`write_whole`] writes `path` under.
pub fn temporary(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".tmp");
    path.with_file_name(name)
}
