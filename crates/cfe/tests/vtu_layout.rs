//! The layout of the VTU files a run writes, read back by an XML parse of their
//! header independent of the writer: every array's offset into the raw appended
//! data is distinct, its block (an 8-byte size, then the values) lies within the
//! data and holds as many values as its type, components and tuples need, the
//! blocks tile the data, and meshio 5.x's way of resolving the offsets (below)
//! finds every array at its own block.

use cfe::analysis::Analysis;
use cfe::model::Model;
use std::collections::{HashMap, HashSet};
use std::path::Path;

/// One `<DataArray>` of the header, in document order.
#[derive(Debug)]
struct Array {
    /// The enclosing section (FieldData, PointData, CellData, Points, Cells).
    section: String,
    attrs: HashMap<String, String>,
}

impl Array {
    fn name(&self) -> &str {
        &self.attrs["Name"]
    }

    fn offset(&self) -> usize {
        self.attrs["offset"].parse().expect("offset is a number")
    }
}

/// A VTU file split at its raw appended data: the header's arrays and the data.
struct Vtu {
    arrays: Vec<Array>,
    points: usize,
    cells: usize,
    data: Vec<u8>,
}

/// The attributes of the element whose text (after its tag name) is `body`.
fn attributes(body: &str) -> HashMap<String, String> {
    let mut attrs = HashMap::new();
    let mut rest = body.trim().trim_end_matches('/').trim();
    while let Some(eq) = rest.find("=\"") {
        let key = rest[..eq].trim().to_string();
        let end = rest[eq + 2..].find('"').expect("unterminated attribute");
        attrs.insert(key, rest[eq + 2..eq + 2 + end].to_string());
        rest = rest[eq + 2 + end + 1..].trim_start();
    }
    attrs
}

fn read(path: &Path) -> Vtu {
    let bytes = std::fs::read(path).unwrap();
    let marker = b"<AppendedData encoding=\"raw\">";
    let start = bytes
        .windows(marker.len())
        .position(|w| w == marker)
        .expect("raw appended data");
    let header = std::str::from_utf8(&bytes[..start]).expect("header is text");
    assert!(header.contains("header_type=\"UInt64\""), "{header}");
    // The data runs from the byte after '_' to the newline before the closing tag.
    let underscore = start
        + marker.len()
        + bytes[start + marker.len()..]
            .iter()
            .position(|&b| b == b'_')
            .unwrap();
    let close = b"\n  </AppendedData>\n</VTKFile>\n";
    assert!(
        bytes.ends_with(close),
        "{}: unexpected ending",
        path.display()
    );
    let data = bytes[underscore + 1..bytes.len() - close.len()].to_vec();

    let mut arrays = Vec::new();
    let (mut points, mut cells) = (None, None);
    let mut section = String::new();
    for element in header.split('<').skip(1) {
        let body = element.split('>').next().unwrap();
        let tag = body.split_whitespace().next().unwrap_or("");
        match tag {
            "FieldData" | "PointData" | "CellData" | "Points" | "Cells" => {
                section = tag.to_string();
            }
            "Piece" => {
                let a = attributes(&body["Piece".len()..]);
                points = Some(a["NumberOfPoints"].parse::<usize>().unwrap());
                cells = Some(a["NumberOfCells"].parse::<usize>().unwrap());
            }
            "DataArray" => {
                let attrs = attributes(&body["DataArray".len()..]);
                assert_eq!(attrs["format"], "appended");
                arrays.push(Array {
                    section: section.clone(),
                    attrs,
                });
            }
            _ => {}
        }
    }
    Vtu {
        arrays,
        points: points.expect("a Piece"),
        cells: cells.expect("a Piece"),
        data,
    }
}

/// The size of the block at `offset`: its leading UInt64.
fn block_size(data: &[u8], offset: usize) -> usize {
    u64::from_le_bytes(data[offset..offset + 8].try_into().unwrap()) as usize
}

/// Offsets distinct, blocks within the data, of the size their arrays need, and
/// tiling the data without gap or overlap.
fn check_offsets(path: &Path, vtu: &Vtu) {
    let what = path.display();
    let mut seen = HashSet::new();
    let mut blocks = Vec::new();
    for a in &vtu.arrays {
        let off = a.offset();
        assert!(
            seen.insert(off),
            "{what}: offset {off} of {} repeated",
            a.name()
        );
        assert!(
            off + 8 <= vtu.data.len(),
            "{what}: {} starts past the data",
            a.name()
        );
        let size = block_size(&vtu.data, off);
        assert!(
            off + 8 + size <= vtu.data.len(),
            "{what}: {} ends past the data",
            a.name()
        );
        let scalar = match a.attrs["type"].as_str() {
            "Float64" | "Int64" | "UInt64" => 8,
            "Int32" | "UInt32" => 4,
            "UInt8" => 1,
            t => panic!("{what}: unexpected type {t}"),
        };
        let components: usize = a
            .attrs
            .get("NumberOfComponents")
            .map_or(1, |c| c.parse().unwrap());
        let values = match (a.section.as_str(), a.name()) {
            ("FieldData", _) => a.attrs["NumberOfTuples"].parse::<usize>().unwrap(),
            ("PointData" | "Points", _) => vtu.points * components,
            ("CellData", _) | ("Cells", "offsets" | "types") => vtu.cells * components,
            // connectivity: as many entries as the last cell offset says.
            ("Cells", "connectivity") => size / scalar,
            (s, n) => panic!("{what}: array {n} in {s}"),
        };
        assert_eq!(size, values * scalar, "{what}: size of {}", a.name());
        blocks.push((off, 8 + size));
    }
    blocks.sort_unstable();
    let mut at = 0;
    for (off, len) in blocks {
        assert_eq!(off, at, "{what}: gap or overlap before offset {off}");
        at += len;
    }
    assert_eq!(at, vtu.data.len(), "{what}: bytes after the last block");
}

/// meshio 5.x's raw-appended reader (`meshio/vtu/_vtu.py`, `_parse_raw_binary`):
/// it walks the blocks from the start of the data; for the block at byte i it
/// takes the first `<DataArray>` in document order whose offset attribute reads
/// i and rewrites that attribute to the block's position in its base64 copy of
/// the data (4 characters per 3 bytes, rounded up). Returns, for each block in
/// data order, the index of the array (in document order) it was given to.
fn meshio_resolution(vtu: &Vtu) -> Vec<usize> {
    let mut offsets: Vec<String> = vtu
        .arrays
        .iter()
        .map(|a| a.attrs["offset"].clone())
        .collect();
    let (mut i, mut base64) = (0usize, 0usize);
    let mut given = Vec::new();
    while i < vtu.data.len() {
        let key = i.to_string();
        let k = offsets
            .iter()
            .position(|o| *o == key)
            .unwrap_or_else(|| panic!("meshio finds no DataArray at offset {i}"));
        offsets[k] = base64.to_string();
        given.push(k);
        let len = 8 + block_size(&vtu.data, i);
        base64 += len.div_ceil(3) * 4;
        i += len;
    }
    given
}

/// The plate on a base, written by `cfe run`'s output path: every `parts_*.vtu`
/// and `pairs_*.vtu` has distinct offsets within the data, blocks of the sizes
/// their arrays need, and meshio's offset resolution gives each block to the
/// array whose offset names it (on the previous layout it gave `displacement`'s
/// block to the field data `LOAD_FACTOR`).
#[test]
fn appended_offsets_are_distinct_and_resolve_as_meshio_reads_them() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/plate_on_base.toml");
    let mut a = Analysis::new(Model::from_file(&file, 1).unwrap()).unwrap();
    let out = std::env::temp_dir().join(format!("cfe-test-vtu-layout-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    a.run(&out, &mut |_| {}).unwrap();
    let mut files: Vec<_> = std::fs::read_dir(out.join("vtu"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "vtu"))
        .collect();
    files.sort();
    for prefix in ["parts_", "pairs_"] {
        assert!(
            files
                .iter()
                .any(|p| p.file_name().unwrap().to_string_lossy().starts_with(prefix)),
            "no {prefix}*.vtu in {files:?}"
        );
    }
    for path in &files {
        let vtu = read(path);
        assert!(
            vtu.arrays.iter().any(|a| a.section == "FieldData"),
            "{}: no field data (the case meshio misread)",
            path.display()
        );
        check_offsets(path, &vtu);
        let mut by_offset: Vec<usize> = (0..vtu.arrays.len()).collect();
        by_offset.sort_unstable_by_key(|&k| vtu.arrays[k].offset());
        let given = meshio_resolution(&vtu);
        for (block, (&k, &own)) in given.iter().zip(&by_offset).enumerate() {
            assert_eq!(
                vtu.arrays[k].name(),
                vtu.arrays[own].name(),
                "{}: meshio gives block {block} to the wrong array",
                path.display()
            );
        }
        assert_eq!(given, by_offset, "{}", path.display());
    }
    let _ = std::fs::remove_dir_all(&out);
}
