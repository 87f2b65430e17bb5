//! Reading the files a user names: bounded by the bytes actually read, not by the size a file
//! reports (`/dev/zero`, a pipe or a FIFO report none and never end), and a file of another kind
//! named for what it is rather than parsed as the wrong format.

use std::io::Read;
use std::path::Path;

/// Why a file could not be read whole.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// Opening or reading it failed.
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// It holds more than `max` bytes (it may never end).
    #[error("more than {} MB: is this the right file?", *max as f64 / 1e6)]
    TooLarge {
        /// The most bytes read.
        max: u64,
    },
}

/// The bytes of `path`, at most `max` of them: a file with more is refused after reading
/// `max + 1`, whatever its metadata says.
pub fn read_at_most(path: &Path, max: u64) -> Result<Vec<u8>, ReadError> {
    let file = std::fs::File::open(path)?;
    let mut bytes = Vec::new();
    file.take(max.saturating_add(1)).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > max {
        return Err(ReadError::TooLarge { max });
    }
    Ok(bytes)
}

/// What a file's first bytes say it is, where that is not a text softgrip reads in its place:
/// "a Gmsh mesh (.msh)", "a PNG image", ... `None` for anything else (TOML, CSV, unknown).
pub fn kind_of(bytes: &[u8]) -> Option<&'static str> {
    let head = &bytes[..bytes.len().min(512)];
    let starts = |p: &[u8]| head.starts_with(p);
    let text = String::from_utf8_lossy(head);
    let first = text.trim_start_matches('\u{feff}').trim_start();
    if first.starts_with("$MeshFormat") {
        Some("a Gmsh mesh (.msh)")
    } else if first.starts_with("# vtk DataFile") {
        Some("a VTK legacy mesh (.vtk)")
    } else if first.starts_with("<?xml") || first.starts_with("<VTKFile") {
        Some(if text.contains("<VTKFile") {
            "a VTK XML file (.vtu)"
        } else {
            "an XML file"
        })
    } else if first.starts_with("solid") && text.contains("facet") {
        Some("an STL surface (.stl)")
    } else if starts(b"\x89PNG") {
        Some("a PNG image")
    } else if starts(b"%PDF") {
        Some("a PDF document")
    } else if starts(b"\x1f\x8b") {
        Some("a gzip archive")
    } else if starts(b"PK\x03\x04") {
        Some("a ZIP archive")
    } else if starts(b"\x7fELF") {
        Some("a program (ELF)")
    } else if first.starts_with("{") || first.starts_with("[{") {
        Some("a JSON file")
    } else if !bytes.is_empty() && head.iter().all(|&b| b == 0) {
        Some("zeros, not text")
    } else {
        None
    }
}

/// `line` shortened for a message: at most `n` characters, so that an error quotes where, not
/// what (a wrong file may be private, or one line of megabytes).
pub fn quote(line: &str, n: usize) -> String {
    match line.char_indices().nth(n) {
        Some((cut, _)) => format!("{}...", &line[..cut]),
        None => line.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_without_end_is_refused_after_the_bytes_allowed() {
        // /dev/zero reports size 0 and never ends.
        let r = read_at_most(Path::new("/dev/zero"), 1000);
        assert!(matches!(r, Err(ReadError::TooLarge { max: 1000 })), "{r:?}");
    }

    #[test]
    fn a_file_within_the_bound_is_read_whole() {
        let dir = std::env::temp_dir().join(format!("softgrip-files-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let p = dir.join("a.txt");
        std::fs::write(&p, b"12345").expect("write");
        assert_eq!(read_at_most(&p, 5).expect("5 bytes"), b"12345");
        assert!(matches!(
            read_at_most(&p, 4),
            Err(ReadError::TooLarge { .. })
        ));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn meshes_images_and_archives_are_told_from_text() {
        assert_eq!(
            kind_of(b"$MeshFormat\n4.1 0 8\n"),
            Some("a Gmsh mesh (.msh)")
        );
        assert_eq!(
            kind_of(b"\xef\xbb\xbf# vtk DataFile Version 3.0\n"),
            Some("a VTK legacy mesh (.vtk)")
        );
        assert_eq!(kind_of(b"\x89PNG\r\n\x1a\n"), Some("a PNG image"));
        assert_eq!(kind_of(&[0u8; 64]), Some("zeros, not text"));
        assert_eq!(kind_of(b"[object]\nshape = \"cuboid\"\n"), None);
        assert_eq!(kind_of(b"time,x,y\n0,1,2\n"), None);
    }

    #[test]
    fn a_quote_is_cut_at_its_length() {
        assert_eq!(quote("root:x:0:0:root:/root:/bin/bash", 8), "root:x:0...");
        assert_eq!(quote("short", 8), "short");
    }
}
