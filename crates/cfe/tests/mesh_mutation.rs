//! Corrupted meshes never crash the reader: every test and example mesh
//! (`tests/data/**/*.msh`, `examples/**/*.msh`) is corrupted in many seeded ways —
//! truncated, tags swapped, random bytes, huge numbers, NaN, sections missing or
//! repeated, lines dropped — and read and checked as a part would be. Each read
//! ends in a mesh or an error, never a panic, and within a bounded time.

use cfe::mesh::gmsh::GmshMesh;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// A small deterministic generator (xorshift64*), so failures reproduce.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

fn meshes() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut out = Vec::new();
    let mut stack = vec![root.join("tests/data"), root.join("examples")];
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "msh") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// The byte ranges of the whitespace-separated tokens of `data`.
fn tokens(data: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, b) in data.iter().enumerate() {
        match (b.is_ascii_whitespace(), start) {
            (false, None) => start = Some(i),
            (true, Some(s)) => {
                out.push((s, i));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push((s, data.len()));
    }
    out
}

/// `data` with the token `t` replaced by `with`.
fn replace_token(data: &[u8], t: (usize, usize), with: &[u8]) -> Vec<u8> {
    [&data[..t.0], with, &data[t.1..]].concat()
}

/// One corruption of `data`, of kind `kind`.
fn mutate(data: &[u8], kind: usize, rng: &mut Rng) -> Vec<u8> {
    let toks = tokens(data);
    let tok = |rng: &mut Rng| toks[rng.below(toks.len())];
    let lines: Vec<&[u8]> = data.split(|&b| b == b'\n').collect();
    let join = |ls: Vec<&[u8]>| ls.join(&b'\n');
    match kind {
        // Truncated anywhere.
        0 => data[..rng.below(data.len())].to_vec(),
        // A run of random bytes.
        1 => {
            let mut d = data.to_vec();
            let at = rng.below(d.len());
            for b in d.iter_mut().skip(at).take(1 + rng.below(16)) {
                *b = rng.next() as u8;
            }
            d
        }
        // Two tokens swapped (tags, counts, coordinates).
        2 => {
            let (a, b) = (tok(rng), tok(rng));
            let (a, b) = if a.0 <= b.0 { (a, b) } else { (b, a) };
            if a == b || a.1 > b.0 {
                return data.to_vec();
            }
            [
                &data[..a.0],
                &data[b.0..b.1],
                &data[a.1..b.0],
                &data[a.0..a.1],
                &data[b.1..],
            ]
            .concat()
        }
        // A token replaced by a hostile number.
        3 => {
            let hostile: [&[u8]; 10] = [
                b"1e308",
                b"-1e308",
                b"nan",
                b"inf",
                b"-0",
                b"18446744073709551616",
                b"4294967296",
                b"-1",
                b"0",
                b"99999999999",
            ];
            replace_token(data, tok(rng), hostile[rng.below(hostile.len())])
        }
        // A line dropped.
        4 => {
            let mut ls = lines.clone();
            ls.remove(rng.below(ls.len()));
            join(ls)
        }
        // A line repeated.
        5 => {
            let mut ls = lines.clone();
            let i = rng.below(ls.len());
            ls.insert(i, lines[i]);
            join(ls)
        }
        // A whole section missing ($Nodes, $Elements, $PhysicalNames, $Entities).
        6 => {
            let names: [&[u8]; 4] = [b"Nodes", b"Elements", b"PhysicalNames", b"Entities"];
            let name = names[rng.below(names.len())];
            let open = [b"$", name].concat();
            let close = [b"$End", name].concat();
            let find = |pat: &[u8]| data.windows(pat.len()).position(|w| w == pat);
            match (find(&open), find(&close)) {
                (Some(a), Some(b)) if b > a => [&data[..a], &data[b + close.len()..]].concat(),
                _ => data.to_vec(),
            }
        }
        // A count inflated (the first token of a random line).
        _ => {
            let t = tok(rng);
            let n = 1u64 << (rng.below(62) + 1);
            replace_token(data, t, n.to_string().as_bytes())
        }
    }
}

/// 60 corruptions of every mesh, each read and (when it reads) turned into a
/// part mesh and checked, with no panic and at most 2 s each.
#[test]
fn corrupted_meshes_never_panic() {
    let files = meshes();
    assert!(files.len() >= 10, "{files:?}");
    let mut rng = Rng(0x5EED_CFE0_2026_1123);
    let mut outcomes = [0usize; 2];
    for file in &files {
        let data = std::fs::read(file).unwrap();
        for round in 0..60 {
            let kind = round % 8;
            let bad = mutate(&data, kind, &mut rng);
            let t = Instant::now();
            let result = std::panic::catch_unwind(|| {
                GmshMesh::parse(&bad, file).and_then(|m| {
                    let mesh = m.part_mesh("part", None)?;
                    mesh.validate("part")
                })
            });
            let took = t.elapsed();
            match result {
                Ok(r) => outcomes[r.is_ok() as usize] += 1,
                Err(_) => panic!(
                    "{}: corruption {round} (kind {kind}) panicked",
                    file.display()
                ),
            }
            assert!(
                took < Duration::from_secs(2),
                "{}: corruption {round} (kind {kind}) took {took:?}",
                file.display()
            );
        }
    }
    // Most corruptions are caught; the rest (e.g. a repeated comment line) read.
    assert!(outcomes[0] > outcomes[1], "errors/accepted: {outcomes:?}");
}
