//! What ties an output file to a checkpoint: its length when the checkpoint
//! was taken and a hash of its last bytes up to there (at most [`TAIL`]).
//! A resumed run continues a file only when both still hold, so rows that
//! another run wrote into the folder after the checkpoint are refused, not
//! continued. The tail holds the last rows, whose step and time columns
//! differ between runs; hashing only the tail keeps a checkpoint of a large
//! file as cheap as one of a small file.

use serde::{Deserialize, Serialize};
use std::io::{Read, Seek, SeekFrom};
use std::path::Path;

/// Bytes hashed at the end of a file.
pub const TAIL: u64 = 4096;

/// An output file's length and tail hash at a checkpoint.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Mark {
    /// Length in bytes.
    pub bytes: u64,
    /// 64-bit FNV-1a of the last `min(bytes, TAIL)` bytes, hex.
    pub tail_fnv: String,
}

fn hex(tail: &[u8]) -> String {
    format!("{:016x}", super::checkpoint::states::fnv(tail))
}

impl Mark {
    /// The mark of a file whose whole content is `bytes`.
    pub fn of_bytes(bytes: &[u8]) -> Self {
        let from = bytes.len().saturating_sub(TAIL as usize);
        Mark {
            bytes: bytes.len() as u64,
            tail_fnv: hex(&bytes[from..]),
        }
    }

    /// The mark of the first `len` bytes of the file at `path`.
    pub fn of_file(path: &Path, len: u64) -> std::io::Result<Self> {
        Ok(Mark {
            bytes: len,
            tail_fnv: hex(&tail(path, len)?),
        })
    }

    /// Why the file at `path` is not the one marked, if it is not: missing,
    /// shorter than the mark, or other bytes before the mark's end.
    pub fn mismatch(&self, path: &Path) -> Option<String> {
        let have = match std::fs::metadata(path) {
            Ok(m) => m.len(),
            Err(e) => return Some(format!("cannot be read ({e})")),
        };
        if have < self.bytes {
            return Some(format!(
                "is {have} bytes, shorter than the {} the checkpoint recorded",
                self.bytes
            ));
        }
        match tail(path, self.bytes) {
            Ok(t) if hex(&t) == self.tail_fnv => None,
            Ok(_) => Some(format!(
                "holds other bytes than the checkpoint recorded before byte {}",
                self.bytes
            )),
            Err(e) => Some(format!("cannot be read ({e})")),
        }
    }
}

/// The last `min(len, TAIL)` bytes of the first `len` of `path`.
fn tail(path: &Path, len: u64) -> std::io::Result<Vec<u8>> {
    let mut f = std::fs::File::open(path)?;
    let from = len.saturating_sub(TAIL);
    f.seek(SeekFrom::Start(from))?;
    let mut buf = vec![0; (len - from) as usize];
    f.read_exact(&mut buf)?;
    Ok(buf)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file's mark is the mark of its bytes; a longer file with the same
    /// prefix keeps it; one changed byte in the tail, or a shorter file,
    /// breaks it.
    #[test]
    fn a_mark_holds_for_the_marked_prefix_only() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("f.csv");
        let rows: Vec<u8> = (0..2000u32)
            .flat_map(|i| format!("{i},{}\n", i * 7).into_bytes())
            .collect();
        std::fs::write(&p, &rows).unwrap();
        let len = 9000;
        let m = Mark::of_file(&p, len).unwrap();
        assert_eq!(m, Mark::of_bytes(&rows[..len as usize]));
        assert_eq!(m.mismatch(&p), None);
        let mut other = rows.clone();
        other[len as usize - 10] ^= 1;
        std::fs::write(&p, &other).unwrap();
        assert!(m.mismatch(&p).unwrap().contains("other bytes"));
        std::fs::write(&p, &rows[..100]).unwrap();
        assert!(m.mismatch(&p).unwrap().contains("shorter"));
        assert!(Mark::of_bytes(b"")
            .mismatch(&dir.path().join("none"))
            .is_some());
    }
}
