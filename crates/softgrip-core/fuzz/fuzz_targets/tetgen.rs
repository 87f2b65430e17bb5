//! Any bytes into the tetgen reader: an error or a mesh, never a panic; what
//! reads also goes through the mesh checks.
#![no_main]

use libfuzzer_sys::fuzz_target;
use softgrip_core::mesh::io::{Format, read_bytes_as};

fuzz_target!(|data: &[u8]| {
    if let Ok(imported) = read_bytes_as(data, Format::Tetgen, "fuzz") {
        let mut mesh = imported.mesh;
        let _ = softgrip_core::mesh::checks::repair(&mut mesh);
    }
});
