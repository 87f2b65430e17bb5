//! VTK XML unstructured grids (`.vtu`, "VTK File Formats", XML section):
//! `ascii`, inline `binary` (base64, optionally zlib-compressed in blocks)
//! and `appended` (raw or base64) data arrays, UInt32 or UInt64 headers.
//! Only the first `<Piece>`; tetrahedra are cell type 10 (24: corners).

use glam::DVec3;

use super::base64;
use super::builder::{Builder, Imported};
use super::error::ImportError;
use super::xml::{Tag, closing, find_tag, section_end};

#[derive(Clone, Copy)]
struct Layout {
    header64: bool,
    compressed: bool,
}

impl Layout {
    fn header_size(self) -> usize {
        if self.header64 { 8 } else { 4 }
    }

    fn read_header(self, b: &[u8], at: usize) -> Option<usize> {
        if self.header64 {
            let v = u64::from_le_bytes(b.get(at..at + 8)?.try_into().ok()?);
            usize::try_from(v).ok()
        } else {
            Some(u32::from_le_bytes(b.get(at..at + 4)?.try_into().ok()?) as usize)
        }
    }
}

/// The bytes of one binary array (uncompressed) from `raw` holding its
/// header and data. Returns the bytes and how many input bytes it used.
fn unpack(raw: &[u8], layout: Layout) -> Result<(Vec<u8>, usize), String> {
    let h = layout.header_size();
    let short = || "the data ends inside an array (truncated?)".to_string();
    if !layout.compressed {
        let n = layout.read_header(raw, 0).ok_or_else(short)?;
        let data = raw
            .get(h..h.checked_add(n).ok_or_else(short)?)
            .ok_or_else(short)?;
        return Ok((data.to_vec(), h + n));
    }
    let blocks = layout.read_header(raw, 0).ok_or_else(short)?;
    let block_size = layout.read_header(raw, h).ok_or_else(short)?;
    let last = layout.read_header(raw, 2 * h).ok_or_else(short)?;
    if blocks > raw.len() / h {
        return Err(format!(
            "{blocks} compressed blocks announced: more than the data holds"
        ));
    }
    let mut sizes = Vec::with_capacity(blocks);
    for k in 0..blocks {
        sizes.push(layout.read_header(raw, (3 + k) * h).ok_or_else(short)?);
    }
    let mut at = (3 + blocks) * h;
    let mut out = Vec::new();
    for (k, size) in sizes.iter().enumerate() {
        let block = raw
            .get(at..at.checked_add(*size).ok_or_else(short)?)
            .ok_or_else(short)?;
        let expected = if k + 1 == blocks && last > 0 {
            last
        } else {
            block_size
        };
        let data = miniz_oxide::inflate::decompress_to_vec_zlib_with_limit(block, expected)
            .map_err(|e| {
                format!(
                    "a compressed block does not inflate (zlib: {:?}): the file is damaged",
                    e.status
                )
            })?;
        out.extend_from_slice(&data);
        at += size;
    }
    Ok((out, at))
}

/// Inline base64 of a compressed array: the block header and the data are
/// encoded separately, back to back.
fn inline_compressed(text: &[u8], layout: Layout) -> Result<Vec<u8>, String> {
    let clean: Vec<u8> = text
        .iter()
        .copied()
        .filter(|c| !c.is_ascii_whitespace())
        .collect();
    let h = layout.header_size();
    let chars = |bytes: usize| bytes.div_ceil(3) * 4;
    let first = base64::decode(clean.get(..chars(h).min(clean.len())).unwrap_or(&[]))?;
    let blocks = layout
        .read_header(&first, 0)
        .ok_or("a truncated array header")?;
    if blocks > clean.len() {
        return Err(format!(
            "{blocks} compressed blocks announced: more than the data holds"
        ));
    }
    let header_chars = chars((3 + blocks) * h);
    let header = base64::decode(
        clean
            .get(..header_chars)
            .ok_or("a truncated array header")?,
    )?;
    let data = base64::decode(&clean[header_chars..])?;
    let mut joined = header[..((3 + blocks) * h).min(header.len())].to_vec();
    joined.extend_from_slice(&data);
    Ok(unpack(&joined, layout)?.0)
}

/// Numbers of a `type` from little-endian bytes.
fn numbers(bytes: &[u8], kind: &str) -> Result<Vec<f64>, String> {
    macro_rules! conv {
        ($t:ty) => {{
            let w = std::mem::size_of::<$t>();
            if bytes.len() % w != 0 {
                return Err(format!(
                    "{} bytes of {kind}: not a whole number of values",
                    bytes.len()
                ));
            }
            bytes
                .chunks_exact(w)
                .map(|c| <$t>::from_le_bytes(c.try_into().expect("chunk")) as f64)
                .collect()
        }};
    }
    Ok(match kind {
        "Float32" => conv!(f32),
        "Float64" => conv!(f64),
        "Int8" => conv!(i8),
        "UInt8" => conv!(u8),
        "Int16" => conv!(i16),
        "UInt16" => conv!(u16),
        "Int32" => conv!(i32),
        "UInt32" => conv!(u32),
        "Int64" => conv!(i64),
        "UInt64" => conv!(u64),
        other => {
            return Err(format!(
                "data type {other:?} is not a VTK type softgrip reads"
            ));
        }
    })
}

struct File<'a> {
    xml: &'a str,
    /// The bytes after `<AppendedData ...>`'s `_`, and whether they are base64.
    appended: Option<(&'a [u8], bool)>,
    layout: Layout,
    name: &'a str,
}

impl File<'_> {
    fn err(&self, message: impl Into<String>) -> ImportError {
        ImportError::at(self.name, None, message)
    }

    /// The values of the `<DataArray>` tag `tag`.
    fn array(&self, tag: &Tag) -> Result<Vec<f64>, ImportError> {
        let what = tag.get("Name").unwrap_or("an array");
        let kind = tag
            .get("type")
            .ok_or_else(|| self.err(format!("DataArray {what} has no type")))?;
        let format = tag.get("format").unwrap_or("ascii");
        let content = || -> Result<&str, ImportError> {
            if tag.self_closing {
                return Ok("");
            }
            let end = closing(self.xml, tag, "DataArray")
                .ok_or_else(|| self.err(format!("DataArray {what} is not closed (truncated?)")))?;
            // The data comes first; VTK may nest <InformationKey> after it.
            let content = &self.xml[tag.end..end];
            Ok(content.split('<').next().unwrap_or(""))
        };
        let bad = |m: String| self.err(format!("DataArray {what}: {m}"));
        match format {
            "ascii" => content()?
                .split_ascii_whitespace()
                .map(|t| {
                    t.parse::<f64>()
                        .map_err(|_| bad(format!("{t:?} is not a number")))
                })
                .collect(),
            "binary" => {
                let text = content()?.as_bytes();
                let bytes = if self.layout.compressed {
                    inline_compressed(text, self.layout).map_err(bad)?
                } else {
                    let raw = base64::decode(text).map_err(bad)?;
                    unpack(&raw, self.layout).map_err(bad)?.0
                };
                numbers(&bytes, kind).map_err(bad)
            }
            "appended" => {
                let (data, encoded) = self
                    .appended
                    .ok_or_else(|| bad("appended, but the file has no AppendedData".into()))?;
                let offset: usize = tag
                    .get("offset")
                    .and_then(|o| o.trim().parse().ok())
                    .ok_or_else(|| bad("appended without an offset".into()))?;
                let from = data
                    .get(offset..)
                    .ok_or_else(|| bad(format!("offset {offset} is past the data")))?;
                let bytes = if encoded {
                    let end = from
                        .iter()
                        .position(|c| *c == b'<' || c.is_ascii_whitespace())
                        .unwrap_or(from.len());
                    let text = &from[..end];
                    if self.layout.compressed {
                        inline_compressed(text, self.layout).map_err(bad)?
                    } else {
                        unpack(&base64::decode(text).map_err(bad)?, self.layout)
                            .map_err(bad)?
                            .0
                    }
                } else {
                    unpack(from, self.layout).map_err(bad)?.0
                };
                numbers(&bytes, kind).map_err(bad)
            }
            other => Err(bad(format!(
                "format {other:?}: expected ascii, binary or appended"
            ))),
        }
    }

    /// The `<DataArray>` inside the section starting at `from` (before
    /// `section_end`) whose Name is `name` (or the first, for `None`).
    fn named(&self, from: usize, section_end: usize, name: Option<&str>) -> Option<Tag<'_>> {
        let mut at = from;
        while let Some(tag) = find_tag(self.xml, at, "DataArray") {
            if tag.end > section_end {
                return None;
            }
            if name.is_none() || tag.get("Name") == name {
                return Some(tag);
            }
            at = tag.end;
        }
        None
    }

    /// The point coordinates of `piece` (x, y, z per point), checked to be
    /// `3 * n_points` values.
    fn coordinates(&self, piece: &Tag, n_points: usize) -> Result<Vec<f64>, ImportError> {
        let points =
            find_tag(self.xml, piece.end, "Points").ok_or_else(|| self.err("no <Points>"))?;
        let points_end = section_end(self.xml, &points, "Points");
        let coords_tag = self
            .named(points.end, points_end, None)
            .ok_or_else(|| self.err("<Points> has no DataArray"))?;
        let coords = self.array(&coords_tag)?;
        if coords.len() != 3 * n_points {
            return Err(self.err(format!(
                "{} point coordinates for the {n_points} points announced",
                coords.len()
            )));
        }
        Ok(coords)
    }

    /// The `<Cells>` arrays of `piece`, checked to hold `n_cells` offsets
    /// and types.
    fn cells(&self, piece: &Tag, n_cells: usize) -> Result<Cells, ImportError> {
        let cells = find_tag(self.xml, piece.end, "Cells").ok_or_else(|| self.err("no <Cells>"))?;
        let cells_end = section_end(self.xml, &cells, "Cells");
        let array = |key: &str| -> Result<Vec<f64>, ImportError> {
            let tag = self
                .named(cells.end, cells_end, Some(key))
                .ok_or_else(|| self.err(format!("<Cells> has no {key} array")))?;
            self.array(&tag)
        };
        let (connectivity, offsets, types) =
            (array("connectivity")?, array("offsets")?, array("types")?);
        if offsets.len() != n_cells || types.len() != n_cells {
            return Err(self.err(format!(
                "{} offsets and {} types for the {n_cells} cells announced",
                offsets.len(),
                types.len()
            )));
        }
        Ok(Cells {
            connectivity,
            offsets,
            types,
        })
    }
}

/// The file's XML, data and layout, checked to be a little-endian
/// UnstructuredGrid; and the byte after its `<VTKFile>` tag.
fn open<'a>(bytes: &'a [u8], name: &'a str) -> Result<(File<'a>, usize), ImportError> {
    let err = |m: String| ImportError::at(name, None, m);
    // Appended raw data is binary: the XML is what comes before it.
    let appended_at = bytes.windows(13).position(|w| w == b"<AppendedData");
    let xml_bytes = &bytes[..appended_at.unwrap_or(bytes.len())];
    let xml = std::str::from_utf8(xml_bytes)
        .map_err(|_| err("not a VTK XML file: not text before its data".into()))?;
    let root = find_tag(xml, 0, "VTKFile")
        .ok_or_else(|| err("not a VTK XML file (no <VTKFile>)".into()))?;
    if root.get("type") != Some("UnstructuredGrid") {
        return Err(err(format!(
            "VTKFile type {:?}: softgrip reads UnstructuredGrid (.vtu) only",
            root.get("type").unwrap_or("")
        )));
    }
    if root.get("byte_order").is_some_and(|b| b != "LittleEndian") {
        return Err(err(
            "big-endian data: softgrip reads LittleEndian .vtu files".into(),
        ));
    }
    let layout = Layout {
        header64: root.get("header_type") == Some("UInt64"),
        compressed: match root.get("compressor") {
            None | Some("") => false,
            Some("vtkZLibDataCompressor") => true,
            Some(other) => {
                return Err(err(format!(
                    "compressor {other}: softgrip reads zlib-compressed or plain files"
                )));
            }
        },
    };
    let appended = match appended_at {
        None => None,
        Some(at) => {
            let rest = &bytes[at..];
            let close = rest
                .iter()
                .position(|c| *c == b'>')
                .ok_or_else(|| err("AppendedData tag not closed".into()))?;
            // The tag's attributes as XML writes them (either quote, spaces around `=`).
            let head = std::str::from_utf8(&rest[..=close]).unwrap_or("");
            let tag = find_tag(head, 0, "AppendedData");
            let encoded = match tag.as_ref().and_then(|t| t.get("encoding")) {
                Some("raw") => false,
                Some("base64") | None => true,
                Some(other) => {
                    return Err(err(format!(
                        "AppendedData encoding \"{other}\": softgrip reads \"raw\" or \"base64\""
                    )));
                }
            };
            let underscore = rest[close..]
                .iter()
                .position(|c| *c == b'_')
                .ok_or_else(|| err("AppendedData without its '_' marker".into()))?;
            Some((&rest[close + underscore + 1..], encoded))
        }
    };
    let file = File {
        xml,
        appended,
        layout,
        name,
    };
    Ok((file, root.end))
}

/// The values of the first `<DataArray>` named `array` in the first
/// `<Piece>`, whichever section holds it (exact for Float64).
pub fn read_array(bytes: &[u8], name: &str, array: &str) -> Result<Vec<f64>, ImportError> {
    let (file, after_root) = open(bytes, name)?;
    let piece = find_tag(file.xml, after_root, "Piece").ok_or_else(|| file.err("no <Piece>"))?;
    let piece_end = section_end(file.xml, &piece, "Piece");
    let tag = file
        .named(piece.end, piece_end, Some(array))
        .ok_or_else(|| file.err(format!("no DataArray named {array:?}")))?;
    file.array(&tag)
}

/// The tetrahedra of a `.vtu`'s first `<Piece>` (other cells skipped).
pub fn read(bytes: &[u8], name: &str) -> Result<Imported, ImportError> {
    let (file, after_root) = open(bytes, name)?;
    let piece = find_tag(file.xml, after_root, "Piece").ok_or_else(|| file.err("no <Piece>"))?;
    let count = |key: &str| -> Result<usize, ImportError> {
        piece
            .get(key)
            .and_then(|v| v.trim().parse().ok())
            .ok_or_else(|| file.err(format!("<Piece> without a valid {key}")))
    };
    let (n_points, n_cells) = (count("NumberOfPoints")?, count("NumberOfCells")?);
    let coords = file.coordinates(&piece, n_points)?;
    let cells = file.cells(&piece, n_cells)?;
    let mut b = Builder::default();
    let err = |m: String| file.err(m);
    for (i, c) in coords.chunks_exact(3).enumerate() {
        let p = DVec3::new(c[0], c[1], c[2]);
        if !p.is_finite() {
            return Err(err(format!("point {i} has a non-finite coordinate {p}")));
        }
        b.node(i as i64, p).map_err(err)?;
    }
    cells.add_to(&mut b).map_err(err)?;
    b.finish().map_err(err)
}

/// The `<Cells>` arrays of a `<Piece>`, as read (VTK's numbers as f64).
struct Cells {
    /// The cells' point indices, one cell after another.
    connectivity: Vec<f64>,
    /// Where each cell's points end in `connectivity` (length: cells).
    offsets: Vec<f64>,
    /// Each cell's VTK type (length: cells).
    types: Vec<f64>,
}

impl Cells {
    /// Adds the tetrahedra (VTK types 10 and 24) to `b` and counts the other
    /// cells as skipped; the error says which cell is malformed.
    fn add_to(&self, b: &mut Builder) -> Result<(), String> {
        let connectivity = &self.connectivity;
        let mut start = 0usize;
        for (k, (&end, &kind)) in self.offsets.iter().zip(&self.types).enumerate() {
            let end = end as usize;
            if end < start || end > connectivity.len() {
                return Err(format!(
                    "cell {k}: offset {end} does not fit the {} connectivity entries",
                    connectivity.len()
                ));
            }
            let nodes = &connectivity[start..end];
            match kind as i64 {
                10 | 24 if nodes.len() >= 4 => {
                    b.tets.push([
                        nodes[0] as i64,
                        nodes[1] as i64,
                        nodes[2] as i64,
                        nodes[3] as i64,
                    ]);
                }
                10 | 24 => {
                    return Err(format!(
                        "cell {k}: a tetrahedron with {} nodes",
                        nodes.len()
                    ));
                }
                other => b.skip(&skipped_kind(other)),
            }
            start = end;
        }
        Ok(())
    }
}

/// What the skip warning calls cells of VTK type `kind`.
fn skipped_kind(kind: i64) -> String {
    match kind {
        1 => "vertices".to_string(),
        3 => "lines".into(),
        5 => "triangles".into(),
        9 => "quads".into(),
        12 => "hexahedra".into(),
        13 => "wedges".into(),
        14 => "pyramids".into(),
        o => format!("cells of type {o}"),
    }
}
