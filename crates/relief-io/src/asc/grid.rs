//! ESRI ASCII grids (`.asc`): a `key value` header, then the rows as text, north row first.
//!
//! ```text
//! ncols         4
//! nrows         2
//! xllcorner     1000.0
//! yllcorner     2000.0
//! cellsize      30.0
//! NODATA_value  -9999
//! 1 2 3 4
//! 5 6 -9999 8
//! ```
//!
//! Keys are case-insensitive: `ncols`, `nrows`, `xllcorner` or `xllcenter`, `yllcorner` or
//! `yllcenter`, `cellsize` or both `dx` and `dy`, and optionally `NODATA_value`. relief
//! reads the coordinates as metres, unless a `.prj` beside the grid names its CRS (ESRI WKT):
//! then degrees are converted to metres, feet too, and the heights are taken in the CRS's
//! linear unit.

use crate::atomic_write::write_atomically;
use crate::format_error::FormatError;
use crate::input_file::open_input;
use crate::raster::{mark_voids, Format, Raster, RasterInfo, ReadOptions};
use crate::{Georeference, IoError};
use relief_core::{DVec2, GridGeometry, HeightField};
use std::fmt::Write as _;
use std::io::{BufRead, BufReader, Read, Write};
use std::path::Path;

/// The longest word (number or key) accepted: room for any `f64` printed in full decimal.
const MAX_WORD: usize = 512;

/// The nodata value [`write_asc`] writes for holes unless a valid height equals it.
const WRITTEN_NODATA: f64 = -9999.0;

/// Reads the ESRI ASCII grid at `path` as a raster, row 0 south.
///
/// The header's keys are case-insensitive; `xllcenter`/`yllcenter` give the centre of the
/// lower-left cell, `xllcorner`/`yllcorner` its lower-left corner; `cellsize` sets both spacings,
/// or `dx` and `dy` each one. The coordinates are taken as metres (`info.georeferenced`, no degree
/// conversion), unless a `.prj` beside the file (ESRI WKT) names a geographic CRS (degrees,
/// converted at the central latitude as for a GeoTIFF) or a projected one in feet (converted, the
/// heights too); its CRS is then the georeference's. Every row must be on a line of its own with
/// exactly `ncols` numbers. Samples equal to `NODATA_value` become NaN. The file is parsed as a
/// stream, word by word.
///
/// Errors: [`IoError::Io`] when the file cannot be read (or is a directory),
/// [`IoError::Format`] naming the line for a missing, repeated or unknown key, a value that
/// is not a number, a row with the wrong count of numbers, too few or too many rows, or a
/// header declaring more samples than the file can hold; [`IoError::Limits`] for a grid over
/// the memory budget; [`IoError::InvalidData`] for a NaN or infinite sample.
pub fn read_asc(path: &Path, options: &ReadOptions) -> Result<Raster, IoError> {
    let (file, len) = open_input(path)?;
    let raster = read_asc_from(BufReader::new(file), len, options).map_err(|e| e.at(path))?;
    crate::georef::sidecars::with_prj(path, raster)
}

/// [`read_asc`] from `reader` holding the `len` bytes of a grid, before the file is named and
/// without the CRS of a `.prj` beside it.
pub(crate) fn read_asc_from<R: Read>(
    reader: R,
    len: u64,
    options: &ReadOptions,
) -> Result<Raster, FormatError> {
    let mut words = Words { reader: BufReader::new(reader), line: 1, word: Vec::new() };
    let header = read_header(&mut words)?;
    let (ncols, nrows) = (header.ncols, header.nrows);
    options.check_samples(ncols, nrows)?;
    // Each sample needs at least a digit and a separator.
    if ncols.saturating_mul(nrows) > len / 2 + 1 {
        return Err(FormatError::Format(format!(
            "header declares {ncols} x {nrows} samples, more than the {len}-byte file can hold"
        )));
    }
    // Both fit in usize: check_size bounds their product.
    let (width, height) = (ncols as usize, nrows as usize);
    let mut samples = vec![0f32; width * height];
    read_rows(&mut words, width, height, &mut samples)?;
    mark_voids(&mut samples, width, header.nodata, true)?;
    let origin = DVec2::new(header.x.corner(header.dx), header.y.corner(header.dy));
    let north = origin.y + height as f64 * header.dy;
    let georeference = Georeference::north_up_grid(origin.x, north, header.dx, header.dy);
    Ok(Raster {
        width,
        height,
        samples,
        geometry: GridGeometry { dx: header.dx, dy: header.dy, z_scale: 1.0, origin },
        info: RasterInfo {
            format: Format::Asc,
            sample_type: "text".into(),
            georeferenced: true,
            height_unit: crate::HeightUnit::default(),
            from_degrees: None,
            nodata: header.nodata,
            georeference: Some(georeference),
        },
    })
}

/// Where the header places the lower-left cell along one axis.
#[derive(Debug, Clone, Copy)]
enum Anchor {
    /// `xllcorner`/`yllcorner`: its outer edge.
    Corner(f64),
    /// `xllcenter`/`yllcenter`: its centre.
    Center(f64),
}

impl Anchor {
    /// The grid's edge for a spacing of `step`.
    fn corner(self, step: f64) -> f64 {
        match self {
            Anchor::Corner(v) => v,
            Anchor::Center(v) => v - 0.5 * step,
        }
    }
}

/// What a header declares.
struct Header {
    ncols: u64,
    nrows: u64,
    x: Anchor,
    y: Anchor,
    dx: f64,
    dy: f64,
    nodata: Option<f64>,
}

/// One lexical item of the file.
#[derive(Debug, PartialEq)]
enum Item {
    /// A run of non-space bytes, in [`Words::word`].
    Word,
    /// The end of a line.
    Newline,
    /// The end of the file.
    End,
}

/// Splits a stream into words and line ends, counting lines, without holding more than a
/// word in memory.
struct Words<R> {
    reader: BufReader<R>,
    /// The line (from 1) of the next byte.
    line: u64,
    /// The last word read.
    word: Vec<u8>,
}

impl<R: Read> Words<R> {
    /// The next word, line end or end of file.
    fn next(&mut self) -> Result<Item, FormatError> {
        self.word.clear();
        loop {
            let buf = self.reader.fill_buf().map_err(FormatError::Io)?;
            if buf.is_empty() {
                return Ok(if self.word.is_empty() { Item::End } else { Item::Word });
            }
            let mut used = 0;
            let (mut found, mut too_long) = (None, false);
            for &b in buf {
                if b.is_ascii_whitespace() {
                    if !self.word.is_empty() {
                        found = Some(Item::Word);
                        break;
                    }
                    used += 1;
                    if b == b'\n' {
                        found = Some(Item::Newline);
                        break;
                    }
                } else if self.word.len() == MAX_WORD {
                    too_long = true;
                    break;
                } else {
                    self.word.push(b);
                    used += 1;
                }
            }
            self.reader.consume(used);
            if too_long {
                return Err(self.error(format!("a word longer than {MAX_WORD} bytes")));
            }
            if let Some(item) = found {
                if item == Item::Newline {
                    self.line += 1;
                }
                return Ok(item);
            }
        }
    }

    /// The last word as text, for messages.
    fn text(&self) -> String {
        String::from_utf8_lossy(&self.word).into_owned()
    }

    /// The last word as a number of type `T`.
    fn number<T: std::str::FromStr>(&self) -> Option<T> {
        std::str::from_utf8(&self.word).ok()?.parse().ok()
    }

    /// A format error at the current line.
    fn error(&self, what: String) -> FormatError {
        FormatError::Format(format!("line {}: {what}", self.line))
    }
}

/// Reads the header, leaving the first sample in `words.word`.
fn read_header<R: Read>(words: &mut Words<R>) -> Result<Header, FormatError> {
    const KEYS: [&str; 10] = [
        "ncols",
        "nrows",
        "xllcorner",
        "xllcenter",
        "yllcorner",
        "yllcenter",
        "cellsize",
        "dx",
        "dy",
        "nodata_value",
    ];
    let mut values: [Option<f64>; 10] = [None; 10];
    let (mut ncols, mut nrows) = (None, None);
    loop {
        match words.next()? {
            Item::Newline => continue,
            Item::End => return Err(words.error("the file ends before any sample".into())),
            Item::Word => {}
        }
        if !words.word[0].is_ascii_alphabetic() {
            break;
        }
        let key = words.text().to_ascii_lowercase();
        let Some(k) = KEYS.iter().position(|&known| known == key) else {
            return Err(words.error(format!("unknown header key '{}'", words.text())));
        };
        if values[k].is_some() {
            return Err(words.error(format!("header key '{key}' given twice")));
        }
        let key_line = words.line;
        if words.next()? != Item::Word {
            let reason = format!("line {key_line}: header key '{key}' has no value");
            return Err(FormatError::Format(reason));
        }
        let value = if k < 2 {
            let count = words.number::<u64>().ok_or_else(|| {
                words.error(format!("{key} '{}' is not a whole number", words.text()))
            })?;
            *(if k == 0 { &mut ncols } else { &mut nrows }) = Some(count);
            count as f64
        } else {
            let value = words.number::<f64>().filter(|v| v.is_finite());
            let value = value.ok_or_else(|| {
                words.error(format!("{key} '{}' is not a finite number", words.text()))
            })?;
            if (6..9).contains(&k) && value <= 0.0 {
                return Err(words.error(format!("{key} {value} is not positive")));
            }
            value
        };
        values[k] = Some(value);
        match words.next()? {
            Item::Newline | Item::End => {}
            Item::Word => {
                return Err(words.error(format!("more than one value after '{key}'")));
            }
        }
    }
    // The first sample is in `words.word`; report missing keys at its line.
    let missing = |key: &str| words.error(format!("the header lacks '{key}' before the samples"));
    let either = |a: usize, b: usize| match (values[a], values[b]) {
        (Some(_), Some(_)) => {
            Err(words.error(format!("the header gives both '{}' and '{}'", KEYS[a], KEYS[b])))
        }
        (Some(v), None) => Ok(Anchor::Corner(v)),
        (None, Some(v)) => Ok(Anchor::Center(v)),
        (None, None) => Err(missing(&format!("{}' or '{}", KEYS[a], KEYS[b]))),
    };
    let x = either(2, 3)?;
    let y = either(4, 5)?;
    let (dx, dy) = match (values[6], values[7], values[8]) {
        (Some(size), None, None) => (size, size),
        (None, Some(dx), Some(dy)) => (dx, dy),
        (Some(_), _, _) => {
            return Err(words.error("the header gives both 'cellsize' and 'dx'/'dy'".into()))
        }
        (None, Some(_), None) => return Err(missing("dy")),
        (None, None, Some(_)) => return Err(missing("dx")),
        (None, None, None) => return Err(missing("cellsize")),
    };
    Ok(Header {
        ncols: ncols.ok_or_else(|| missing("ncols"))?,
        nrows: nrows.ok_or_else(|| missing("nrows"))?,
        x,
        y,
        dx,
        dy,
        nodata: values[9],
    })
}

/// Reads `height` rows of `width` samples, the first already in `words.word`, north row first,
/// into `samples` (row 0 south). Then only blank lines may follow.
fn read_rows<R: Read>(
    words: &mut Words<R>,
    width: usize,
    height: usize,
    samples: &mut [f32],
) -> Result<(), FormatError> {
    let mut item = Item::Word;
    let (mut row, mut col) = (0, 0);
    while row < height {
        match item {
            Item::Word => {
                if col == width {
                    return Err(words.error(format!(
                        "row {} has more than the {width} samples of ncols",
                        row + 1
                    )));
                }
                let value = words.number::<f32>().ok_or_else(|| {
                    words.error(format!("sample '{}' is not a number", words.text()))
                })?;
                samples[(height - 1 - row) * width + col] = value;
                col += 1;
            }
            Item::Newline | Item::End if col == width => {
                row += 1;
                col = 0;
            }
            Item::Newline if col == 0 => {}
            Item::End if col == 0 => {
                return Err(
                    words.error(format!("the file ends after {row} of the {height} rows of nrows"))
                );
            }
            Item::Newline | Item::End => {
                // The line count has moved past the line end: name the row's own line.
                let line = words.line - u64::from(item == Item::Newline);
                return Err(FormatError::Format(format!(
                    "line {line}: row {} has {col} samples, ncols is {width}",
                    row + 1
                )));
            }
        }
        if row < height {
            item = words.next()?;
        }
    }
    loop {
        match words.next()? {
            Item::Newline => {}
            Item::End => return Ok(()),
            Item::Word => {
                return Err(words.error(format!("more data after the {height} rows of nrows")));
            }
        }
    }
}

/// Writes `field` as an ESRI ASCII grid, north row first.
///
/// The header gives `ncols`, `nrows`, `xllcorner` and `yllcorner` (the grid's south-west
/// corner, its origin), then `cellsize` when `dx == dy`, else `dx` and `dy` (an extension
/// GDAL reads). When the field has holes, they are written as `NODATA_value` -9999 (or, if a
/// valid height is -9999, a lower value no height takes); a field without holes gets no
/// `NODATA_value`, so no valid height can be mistaken for one.
///
/// Heights are world heights, `sample * z_scale`, rounded to f32 and printed with the fewest
/// digits that read back to the same f32: with `z_scale` 1 the samples round-trip exactly.
/// The file is written atomically.
///
/// Errors: [`IoError::InvalidData`] for a height that overflows f32 once scaled,
/// [`IoError::Io`] when the file cannot be written.
pub fn write_asc(path: &Path, field: &HeightField) -> Result<(), IoError> {
    let (width, height) = (field.width(), field.height());
    let geometry = field.geometry();
    let world = |col, row| (f64::from(field.sample(col, row)) * geometry.z_scale) as f32;
    let mut header = format!("ncols {width}\nnrows {height}\n");
    let _ = write!(header, "xllcorner {}\nyllcorner {}\n", geometry.origin.x, geometry.origin.y);
    if geometry.dx == geometry.dy {
        let _ = writeln!(header, "cellsize {}", geometry.dx);
    } else {
        let _ = write!(header, "dx {}\ndy {}\n", geometry.dx, geometry.dy);
    }
    let nodata = if field.hole_count() > 0 {
        let valid = |v: f32| {
            (0..height).any(|row| (0..width).any(|c| !field.is_hole(c, row) && world(c, row) == v))
        };
        // -9999, -99999, ... : the first that no valid height takes.
        let nodata = std::iter::successors(Some(WRITTEN_NODATA), |v| Some(v * 10.0 - 9.0))
            .take(30)
            .map(|v| v as f32)
            .find(|&v| !valid(v))
            .ok_or_else(|| IoError::invalid_data(path, "no free NODATA_value for the holes"))?;
        let _ = writeln!(header, "NODATA_value {nodata}");
        Some(nodata)
    } else {
        None
    };
    write_atomically(path, |w| {
        let io = |e| IoError::io(path, e);
        w.write_all(header.as_bytes()).map_err(io)?;
        let mut line = String::new();
        for row in (0..height).rev() {
            line.clear();
            for col in 0..width {
                let value = match nodata {
                    Some(nodata) if field.is_hole(col, row) => nodata,
                    _ => world(col, row),
                };
                if !value.is_finite() {
                    return Err(IoError::invalid_data(
                        path,
                        format!(
                            "height at column {col}, row {row} overflows f32 once scaled by {}",
                            geometry.z_scale
                        ),
                    ));
                }
                if col > 0 {
                    line.push(' ');
                }
                let _ = write!(line, "{value}");
            }
            line.push('\n');
            w.write_all(line.as_bytes()).map_err(io)?;
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<Raster, IoError> {
        let path = Path::new("grid.asc");
        read_asc_from(text.as_bytes(), text.len() as u64, &ReadOptions::default())
            .map_err(|e| e.at(path))
    }

    fn format_error(text: &str) -> String {
        match read(text) {
            Err(err @ IoError::Format { .. }) => err.to_string(),
            other => panic!("expected a format error for {text:?}, got {other:?}"),
        }
    }

    const HEAD: &str = "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n";

    #[test]
    fn reads_a_small_grid_flipped() {
        let r = read(&format!("{HEAD}1 2\n3 4\n")).unwrap();
        assert_eq!(r.samples, [3.0, 4.0, 1.0, 2.0]);
        let r = read(&format!("{HEAD}\n1 2\r\n\n3\t4")).unwrap();
        assert_eq!(r.samples, [3.0, 4.0, 1.0, 2.0]);
    }

    #[test]
    fn broken_files_name_their_line() {
        let cases = [
            (format!("{HEAD}1 2\n3\n"), "line 7: row 2 has 1 samples"),
            (format!("{HEAD}1 2 5\n3 4\n"), "line 6: row 1 has more than the 2"),
            (format!("{HEAD}1 x\n3 4\n"), "line 6: sample 'x' is not a number"),
            (format!("{HEAD}1 2\n"), "after 1 of the 2 rows"),
            (format!("{HEAD}1 2\n3 4\n5\n"), "line 8: more data after the 2 rows"),
            (format!("{HEAD}1 2\n3 4"), ""),
            (
                "ncols 2\nnrows 2\nxllcorner 0\ncellsize 1\n1 2\n3 4\n".into(),
                "line 5: the header lacks 'yllcorner' or 'yllcenter'",
            ),
            (format!("ncols 2\n{HEAD}1 2\n3 4\n"), "line 2: header key 'ncols' given twice"),
            (format!("{HEAD}xllcenter 3\n1 2\n3 4\n"), "both 'xllcorner' and 'xllcenter'"),
            (format!("{HEAD}dx 3\n1 2\n3 4\n"), "both 'cellsize' and 'dx'/'dy'"),
            (format!("ncols 2.5\n{HEAD}"), "line 1: ncols '2.5' is not a whole number"),
            (format!("cellsize -1\n{HEAD}"), "line 1: cellsize -1 is not positive"),
            (format!("color 3\n{HEAD}"), "line 1: unknown header key 'color'"),
            (format!("nrows\n{HEAD}"), "line 1: header key 'nrows' has no value"),
            (format!("nrows 1 2\n{HEAD}"), "line 1: more than one value after 'nrows'"),
            (HEAD.to_string(), "ends before any sample"),
        ];
        for (text, expected) in cases {
            if expected.is_empty() {
                assert!(read(&text).is_ok(), "{text:?}");
                continue;
            }
            let err = format_error(&text);
            assert!(err.contains(expected), "{err} does not contain {expected}");
        }
    }

    #[test]
    fn a_very_long_word_is_refused() {
        let err = format_error(&format!("{HEAD}1{} 2\n3 4\n", "0".repeat(MAX_WORD)));
        assert!(err.contains("longer than"), "{err}");
    }
}
