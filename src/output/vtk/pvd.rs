//! The `.pvd` collection that ParaView opens as an animation: one
//! `DataSet` per frame with its physical time. The file is valid after every
//! frame: each new entry overwrites the closing tags and writes them again.
//! A checkpoint records the length without the closing tags, so a resumed
//! run (or a copy of the folder cut to the checkpoint) continues the list.

use crate::error::{Error, Result};
use std::fs::File;
use std::io::{Seek, SeekFrom, Write};
use std::path::PathBuf;

const HEAD: &str = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<Collection>\n";
const TAIL: &str = "</Collection>\n</VTKFile>\n";

/// An open `.pvd` file.
pub(crate) struct Pvd {
    pub path: PathBuf,
    file: Option<File>,
    /// Bytes before the closing tags.
    pub body_len: u64,
}

impl Pvd {
    pub fn at(path: PathBuf) -> Self {
        Pvd {
            path,
            file: None,
            body_len: 0,
        }
    }

    /// A new, empty collection.
    pub fn create(&mut self) -> Result<()> {
        // Whole or not at all (a temporary file renamed over any older
        // collection), then opened to append.
        crate::output::file::write_whole(&self.path, (HEAD.to_owned() + TAIL).as_bytes())?;
        self.reopen(HEAD.len() as u64)
    }

    /// Continue a collection cut to `len` bytes (a checkpoint's length).
    pub fn reopen(&mut self, len: u64) -> Result<()> {
        let mut f = crate::output::file::reopen_cut(&self.path, len)?;
        f.write_all(TAIL.as_bytes())
            .map_err(|e| Error::io(&self.path, e))?;
        self.body_len = len;
        self.file = Some(f);
        Ok(())
    }

    /// Rename every frame the collection lists by `rename` (the frames of a
    /// resumed series renumbered), keeping each entry's time.
    pub fn rewrite_files(&mut self, rename: impl Fn(&str) -> String) -> Result<()> {
        let path = &self.path;
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
        let body = text
            .get(..self.body_len as usize)
            .ok_or_else(|| Error::io(path, std::io::Error::other("shorter than its checkpoint")))?;
        let mut out = String::with_capacity(text.len());
        for line in body.split_inclusive('\n') {
            match line.split_once(" file=\"") {
                Some((head, rest)) => match rest.split_once('"') {
                    Some((file, tail)) => {
                        out += &format!("{head} file=\"{}\"{tail}", rename(file));
                    }
                    None => out += line,
                },
                None => out += line,
            }
        }
        // Whole or not at all (a temporary file renamed over it), then
        // opened again to go on appending.
        self.file = None;
        crate::output::file::write_whole(path, (out.clone() + TAIL).as_bytes())?;
        self.reopen(out.len() as u64)
    }

    /// Add the frame `file` (relative to the collection) at time `t`.
    pub fn push(&mut self, t: f64, file: &str) -> Result<()> {
        let path = &self.path;
        let f = self
            .file
            .as_mut()
            .ok_or_else(|| super::super::file::not_open(path))?;
        let entry = format!(
            "<DataSet timestep=\"{}\" part=\"0\" file=\"{file}\"/>\n",
            ryu::Buffer::new().format(t)
        );
        let written = f
            .seek(SeekFrom::Start(self.body_len))
            .and_then(|_| f.write_all(entry.as_bytes()))
            .and_then(|_| f.write_all(TAIL.as_bytes()));
        if let Err(e) = written {
            // A full disk: back to the entries before, closed again, so
            // the collection stays valid XML.
            let _ = f
                .set_len(self.body_len)
                .and_then(|_| f.seek(SeekFrom::Start(self.body_len)))
                .and_then(|_| f.write_all(TAIL.as_bytes()));
            return Err(Error::io(path, e));
        }
        self.body_len += entry.len() as u64;
        Ok(())
    }

    /// The mark of the entries so far (without the closing tags), for a
    /// checkpoint.
    pub fn mark(&self) -> Result<crate::output::mark::Mark> {
        crate::output::mark::Mark::of_file(&self.path, self.body_len)
            .map_err(|e| Error::io(&self.path, e))
    }
}
