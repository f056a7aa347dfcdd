//! CSV files of the observers: create, continue after a checkpoint, flush.

use crate::error::{Error, Result};
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// A CSV output file of an observer, opened when the run starts: created
/// with its header ([`CsvFile::create`]) or continued after a checkpoint
/// ([`CsvFile::reopen`]).
pub struct CsvFile {
    /// The file's path.
    pub path: PathBuf,
    pub(crate) w: Option<csv::Writer<BufWriter<File>>>,
}

/// The error of a file written before it was opened (a bug, reported, not a panic).
pub(crate) fn not_open(path: &Path) -> Error {
    Error::io(path, std::io::Error::other("written before it was opened"))
}

pub(crate) fn csv_err(path: &Path, e: csv::Error) -> Error {
    Error::io(path, std::io::Error::other(e.to_string()))
}

impl CsvFile {
    /// The file at `path`, not yet opened.
    pub fn at(path: PathBuf) -> Self {
        CsvFile { path, w: None }
    }

    /// Create the file with its header row.
    pub fn create(&mut self, header: &[&str]) -> Result<()> {
        let path = &self.path;
        let f = File::create(path).map_err(|e| Error::io(path, e))?;
        let mut w = csv::Writer::from_writer(BufWriter::new(f));
        w.write_record(header).map_err(|e| csv_err(path, e))?;
        self.w = Some(w);
        Ok(())
    }

    /// The open writer (an I/O error, not a panic, if it was never opened).
    pub fn writer(&mut self) -> Result<&mut csv::Writer<BufWriter<File>>> {
        let path = &self.path;
        self.w.as_mut().ok_or_else(|| not_open(path))
    }

    /// Open the file for appending after cutting it to `len` bytes (resume).
    pub fn reopen(&mut self, len: u64) -> Result<()> {
        let f = reopen_cut(&self.path, len)?;
        let w = csv::WriterBuilder::new()
            .has_headers(false)
            .from_writer(BufWriter::new(f));
        self.w = Some(w);
        Ok(())
    }

    /// Flush and return the file's length (for a checkpoint).
    pub fn flushed_len(&mut self) -> Result<u64> {
        self.flush()?;
        let f = self.writer()?.get_ref().get_ref();
        let len = f.metadata().map(|m| m.len());
        len.map_err(|e| Error::io(&self.path, e))
    }

    /// Flush what is written (nothing to do for a file never opened).
    pub fn flush(&mut self) -> Result<()> {
        match &mut self.w {
            Some(w) => w.flush().map_err(|e| Error::io(&self.path, e)),
            None => Ok(()),
        }
    }

    /// The file name, as checkpoints record it.
    pub fn name(&self) -> String {
        self.path
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
    }
}

/// An output file a checkpoint continues, cut to the `len` bytes it
/// recorded and positioned at its end; bad input if it is missing or shorter.
pub(crate) fn reopen_cut(path: &Path, len: u64) -> Result<File> {
    use std::io::{Seek, SeekFrom};
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
