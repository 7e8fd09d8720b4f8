//! Reading an input file — a problem file or a mesh file — with the guards every
//! read needs: only a regular file is read (a FIFO, a terminal or another device, a
//! socket or a directory is refused before anything is read from it, as reading
//! one may block forever or never end), and no more than a cap for its kind.
//!
//! Every place the library reads a problem or mesh file goes through [`read`].

use crate::error::{Error, InputRefusal, Result};
use std::io::Read;
use std::path::Path;

/// The largest problem file read: 64 MiB. A problem file is a few kilobytes of
/// TOML; its meshes, however large, live in their own files.
pub const PROBLEM_FILE_CAP: u64 = 64 << 20;

/// The largest mesh (Gmsh) file read: 4 GiB. An ASCII MSH 4.1 file takes about
/// 70 bytes per node and 45 per triangle, so the benchmark's largest model (8 M
/// unknowns, 4 M nodes, 8 M triangles) is about 0.65 GB; 4 GiB holds a mesh of
/// some 25 M nodes, more than a solve of that size can hold in memory.
pub const MESH_FILE_CAP: u64 = 4 << 30;

/// What a file is, for a refusal's message.
fn file_type_name(t: std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if t.is_dir() {
        "a directory"
    } else if t.is_fifo() {
        "a FIFO (named pipe)"
    } else if t.is_char_device() {
        "a character device"
    } else if t.is_block_device() {
        "a block device"
    } else if t.is_socket() {
        "a socket"
    } else if t.is_symlink() {
        "a symbolic link"
    } else {
        "not a regular file"
    }
}

/// `n` bytes in the largest binary unit that divides it (`64 MiB`, `4 GiB`).
fn bytes_text(n: u64) -> String {
    for (shift, unit) in [(30, "GiB"), (20, "MiB"), (10, "KiB")] {
        if n >= 1 << shift && n.is_multiple_of(1 << shift) {
            return format!("{} {unit}", n >> shift);
        }
    }
    format!("{n} bytes")
}

/// The refusal of `path` (described as `what`, e.g. "problem file").
fn refused(path: &Path, what: &str, refusal: InputRefusal) -> Error {
    let message = match refusal {
        InputRefusal::NotRegular { found } => format!(
            "it is {found}, not a regular file; cfe reads problem and mesh files only from regular files (reading a pipe or a device could block forever or never end): save the input to a file and give its path"
        ),
        InputRefusal::TooLarge { size, cap } => format!(
            "it holds {}{size} bytes, more than the {} cap on a {what}",
            if size > cap { "" } else { "at least " },
            bytes_text(cap),
        ),
    };
    Error::InputFile {
        path: path.to_path_buf(),
        what: what.to_string(),
        refusal,
        message,
    }
}

/// The contents of the regular file at `path`, of at most `cap` bytes. `what`
/// names the file in messages ("problem file", "Gmsh file"); `io` turns an
/// operating-system error (no such file, no permission) into the caller's error.
///
/// The file's type is checked before it is opened (`std::fs::metadata`), and again
/// on the opened file, which is opened without blocking (`O_NONBLOCK`, so a FIFO
/// swapped in between cannot block either). Refusals are
/// [`Error::InputFile`]: not a regular file, or larger than `cap` (checked on the
/// size the file reports and again while reading, for files that grow or report
/// no size).
pub fn read(
    path: &Path,
    what: &str,
    cap: u64,
    io: impl Fn(std::io::Error) -> Error,
) -> Result<Vec<u8>> {
    use std::os::unix::fs::OpenOptionsExt;
    let check = |meta: &std::fs::Metadata| -> Result<()> {
        if !meta.is_file() {
            return Err(refused(
                path,
                what,
                InputRefusal::NotRegular {
                    found: file_type_name(meta.file_type()),
                },
            ));
        }
        if meta.len() > cap {
            return Err(refused(
                path,
                what,
                InputRefusal::TooLarge {
                    size: meta.len(),
                    cap,
                },
            ));
        }
        Ok(())
    };
    check(&std::fs::metadata(path).map_err(&io)?)?;
    let file = std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NONBLOCK)
        .open(path)
        .map_err(&io)?;
    let meta = file.metadata().map_err(&io)?;
    check(&meta)?;
    let mut data = Vec::with_capacity(usize::try_from(meta.len()).unwrap_or(0));
    file.take(cap.saturating_add(1))
        .read_to_end(&mut data)
        .map_err(&io)?;
    let size = data.len() as u64;
    if size > cap {
        return Err(refused(path, what, InputRefusal::TooLarge { size, cap }));
    }
    Ok(data)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Caps are named in binary units.
    #[test]
    fn caps_are_named_in_binary_units() {
        assert_eq!(bytes_text(PROBLEM_FILE_CAP), "64 MiB");
        assert_eq!(bytes_text(MESH_FILE_CAP), "4 GiB");
        assert_eq!(bytes_text(1000), "1000 bytes");
    }
}
