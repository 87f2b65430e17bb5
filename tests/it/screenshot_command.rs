//! `softgrip screenshot` renders the built-in scene headless to a PNG.
#![cfg(feature = "gui")]

use crate::support::{arg, scratch_path, softgrip};

/// The command itself writes the picture.
#[test]
fn screenshot_command_writes_a_png() {
    let out = scratch_path("softgrip-shot").with_extension("png");
    let status = softgrip(&[
        "screenshot",
        "--at",
        "0.05",
        "--size",
        "160x120",
        "--view",
        "front",
        "--out",
        arg(&out),
    ])
    .status;
    assert!(status.success());
    let image = image::open(&out).expect("a PNG").to_rgba8();
    assert_eq!(image.dimensions(), (160, 120));
    assert!(image.pixels().any(is_finger) && image.pixels().any(is_object));
    let _ = std::fs::remove_file(out);
}

/// The finger's blue, whatever the shading.
fn is_finger(p: &image::Rgba<u8>) -> bool {
    let [r, g, b, _] = p.0;
    b > 120 && b as i32 > r as i32 + 50 && b as i32 > g as i32 + 20
}

/// The object's orange, whatever the shading.
fn is_object(p: &image::Rgba<u8>) -> bool {
    let [r, g, b, _] = p.0;
    r > 100 && r > g && g > b
}
