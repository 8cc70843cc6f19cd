//! The journal of a cloud-optimised GeoTIFF being written, which lets a rerun resume it: JSON
//! lines, first a header saying which job it is (size, bands, tile, nodata, orientation and
//! the caller's fingerprint), then one line per block written, with where each of its tiles
//! lies in the spill. A line is appended (and synced) only once its tiles are synced in the
//! spill, so every complete line describes tiles that are there.

use crate::IoError;
use serde_json::{json, Value};
use std::fs::{File, OpenOptions};
use std::io::{BufRead, BufReader, Seek, SeekFrom, Write};
use std::ops::Range;
use std::path::{Path, PathBuf};

/// Version of the journal's format, in its header.
const VERSION: u64 = 1;

/// What identifies a job: a journal resumes only a job whose header is the same.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct JournalHeader {
    /// Columns.
    pub(crate) width: usize,
    /// Rows.
    pub(crate) height: usize,
    /// The bands' names.
    pub(crate) bands: Vec<String>,
    /// Side of a tile.
    pub(crate) tile: usize,
    /// The nodata value voids are written as.
    pub(crate) nodata: Option<f64>,
    /// Whether file row 0 is the grid's southern row.
    pub(crate) south_up: bool,
    /// The caller's identification of its input and options.
    pub(crate) fingerprint: String,
}

impl JournalHeader {
    /// The header line's JSON (nodata by its bits, so that NaN and -0 are told apart).
    fn to_json(&self) -> Value {
        json!({
            "relief_cog_journal": VERSION,
            "width": self.width,
            "height": self.height,
            "bands": self.bands,
            "tile": self.tile,
            "nodata_bits": self.nodata.map(f64::to_bits),
            "south_up": self.south_up,
            "fingerprint": self.fingerprint,
        })
    }
}

/// One block as the journal records it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct JournalBlock {
    /// Grid columns.
    pub(crate) cols: Range<usize>,
    /// Grid rows (row 0 south).
    pub(crate) rows: Range<usize>,
    /// Whether some sample of the block was a void.
    pub(crate) voids: bool,
    /// Offset and byte count in the spill of each of the block's tiles, in the order the
    /// writer lists them.
    pub(crate) tiles: Vec<(u64, u32)>,
}

impl JournalBlock {
    /// The block's line (without its newline).
    fn to_line(&self) -> String {
        let tiles: Vec<u64> =
            self.tiles.iter().flat_map(|&(offset, count)| [offset, u64::from(count)]).collect();
        json!({
            "cols": [self.cols.start, self.cols.end],
            "rows": [self.rows.start, self.rows.end],
            "voids": self.voids,
            "tiles": tiles,
        })
        .to_string()
    }

    /// The block of a line; `None` when it is not one.
    fn from_line(line: &str) -> Option<JournalBlock> {
        let value: Value = serde_json::from_str(line).ok()?;
        let range = |key: &str| -> Option<Range<usize>> {
            let pair = value.get(key)?.as_array()?;
            let bound = |i: usize| usize::try_from(pair.get(i)?.as_u64()?).ok();
            (pair.len() == 2).then_some(bound(0)?..bound(1)?)
        };
        let numbers = value.get("tiles")?.as_array()?;
        if !numbers.len().is_multiple_of(2) {
            return None;
        }
        let mut tiles = Vec::with_capacity(numbers.len() / 2);
        for pair in numbers.chunks_exact(2) {
            let count = u32::try_from(pair[1].as_u64()?).ok()?;
            tiles.push((pair[0].as_u64()?, count));
        }
        Some(JournalBlock {
            cols: range("cols")?,
            rows: range("rows")?,
            voids: value.get("voids")?.as_bool()?,
            tiles,
        })
    }
}

/// The journal file, open for appending block lines.
pub(crate) struct Journal {
    path: PathBuf,
    file: File,
    /// Bytes of complete lines.
    len: u64,
}

impl Journal {
    /// Creates (or replaces) the journal at `path` with `header`'s line, synced.
    pub(crate) fn create(path: &Path, header: &JournalHeader) -> Result<Journal, IoError> {
        let file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(true)
            .open(path)
            .map_err(|e| IoError::io(path, e))?;
        let mut journal = Journal { path: path.to_path_buf(), file, len: 0 };
        journal.append_line(&header.to_json().to_string())?;
        Ok(journal)
    }

    /// Reopens the journal an earlier writer left at `path` if its header is `header`:
    /// `None` when there is none or it is another job's. Its block lines are given in order
    /// to `accept`, up to the first that is not a whole line of a block or that `accept`
    /// refuses: that line and those after it are cut from the file (their blocks are to be
    /// written again).
    pub(crate) fn resume(
        path: &Path,
        header: &JournalHeader,
        mut accept: impl FnMut(JournalBlock) -> bool,
    ) -> Result<Option<Journal>, IoError> {
        let file = match OpenOptions::new().read(true).write(true).open(path) {
            Ok(file) => file,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(IoError::io(path, e)),
        };
        let mut reader = BufReader::new(&file);
        let mut line = String::new();
        let mut len = 0u64;
        let read = |reader: &mut BufReader<&File>, line: &mut String| {
            line.clear();
            // Bytes that are not UTF-8 make a line that is not one: stop there.
            reader.read_line(line).unwrap_or(0)
        };
        let n = read(&mut reader, &mut line);
        let same_job = line.ends_with('\n')
            && serde_json::from_str::<Value>(&line).is_ok_and(|v| v == header.to_json());
        if !same_job {
            return Ok(None);
        }
        len += n as u64;
        loop {
            let n = read(&mut reader, &mut line);
            if n == 0 || !line.ends_with('\n') {
                break;
            }
            if !JournalBlock::from_line(&line).is_some_and(&mut accept) {
                break;
            }
            len += n as u64;
        }
        drop(reader);
        file.set_len(len).map_err(|e| IoError::io(path, e))?;
        file.sync_data().map_err(|e| IoError::io(path, e))?;
        Ok(Some(Journal { path: path.to_path_buf(), file, len }))
    }

    /// Appends `block`'s line and syncs it.
    pub(crate) fn append(&mut self, block: &JournalBlock) -> Result<(), IoError> {
        self.append_line(&block.to_line())
    }

    /// Appends `line` and a newline, synced; on failure the journal is cut back to its
    /// complete lines (as far as the system lets it).
    fn append_line(&mut self, line: &str) -> Result<(), IoError> {
        let mut bytes = Vec::with_capacity(line.len() + 1);
        bytes.extend_from_slice(line.as_bytes());
        bytes.push(b'\n');
        let written = self
            .file
            .seek(SeekFrom::Start(self.len))
            .and_then(|_| self.file.write_all(&bytes))
            .and_then(|()| self.file.sync_data());
        if let Err(e) = written {
            let _ = self.file.set_len(self.len);
            return Err(IoError::io(&self.path, e));
        }
        self.len += bytes.len() as u64;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_dir::TestDir;

    fn header(fingerprint: &str) -> JournalHeader {
        JournalHeader {
            width: 300,
            height: 200,
            bands: vec!["a".into(), "b \"c\"".into()],
            tile: 128,
            nodata: Some(f64::NAN),
            south_up: false,
            fingerprint: fingerprint.into(),
        }
    }

    fn block(k: u64) -> JournalBlock {
        JournalBlock {
            cols: 0..128,
            rows: 72..200,
            voids: k.is_multiple_of(2),
            tiles: vec![(k, 7), (k + 7, 9)],
        }
    }

    #[test]
    fn blocks_replay_in_order_and_a_truncated_last_line_is_cut() {
        let dir = TestDir::new("cog-journal");
        let path = dir.path().join("journal");
        let mut journal = Journal::create(&path, &header("job")).unwrap();
        for k in 0..3 {
            journal.append(&block(k * 16)).unwrap();
        }
        drop(journal);
        let whole = std::fs::read(&path).unwrap();
        // A kill in the middle of the last line.
        std::fs::write(&path, &whole[..whole.len() - 5]).unwrap();
        let mut seen = Vec::new();
        let journal = Journal::resume(&path, &header("job"), |b| {
            seen.push(b);
            true
        })
        .unwrap();
        assert!(journal.is_some());
        assert_eq!(seen, [block(0), block(16)]);
        let cut = std::fs::read(&path).unwrap();
        assert!(cut.ends_with(b"\n") && cut.len() < whole.len() - 5);
        // Appending goes on after the complete lines; a refused block cuts the rest.
        journal.unwrap().append(&block(99)).unwrap();
        let mut seen = Vec::new();
        Journal::resume(&path, &header("job"), |b| {
            seen.push(b.tiles[0].0);
            b.tiles[0].0 != 16
        })
        .unwrap()
        .unwrap();
        assert_eq!(seen, [0, 16]);
        let mut seen = 0;
        Journal::resume(&path, &header("job"), |_| {
            seen += 1;
            true
        })
        .unwrap();
        assert_eq!(seen, 1);
    }

    #[test]
    fn another_job_or_no_journal_is_not_resumed() {
        let dir = TestDir::new("cog-journal-other");
        let path = dir.path().join("journal");
        assert!(Journal::resume(&path, &header("job"), |_| true).unwrap().is_none());
        Journal::create(&path, &header("job")).unwrap();
        assert!(Journal::resume(&path, &header("other"), |_| true).unwrap().is_none());
        let zero = JournalHeader { nodata: Some(0.0), ..header("job") };
        let minus_zero = JournalHeader { nodata: Some(-0.0), ..header("job") };
        Journal::create(&path, &zero).unwrap();
        assert!(Journal::resume(&path, &minus_zero, |_| true).unwrap().is_none());
        assert!(Journal::resume(&path, &zero, |_| true).unwrap().is_some());
        std::fs::write(&path, b"not json\n").unwrap();
        assert!(Journal::resume(&path, &zero, |_| true).unwrap().is_none());
        assert_eq!(JournalBlock::from_line("{\"cols\":[0,1]}"), None);
        let line = block(3).to_line();
        assert_eq!(JournalBlock::from_line(&line), Some(block(3)));
    }
}
