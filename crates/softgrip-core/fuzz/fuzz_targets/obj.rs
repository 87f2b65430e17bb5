//! Any bytes into the obj surface reader and its checks: an error or a
//! surface, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use softgrip_core::mesh::surface;

fuzz_target!(|data: &[u8]| {
    if let Ok(s) = surface::read(data, "fuzz", true) {
        let _ = surface::check(&s, "fuzz");
    }
});
