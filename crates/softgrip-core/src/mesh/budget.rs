//! The element budget: a scene's mesh is counted before it is built, so that a tiny
//! `edge_length` is an error naming the count and the memory, not an abort when the allocation
//! fails (1e-7 m on a 20 mm cube asked for 7.7e17 bytes).

use std::sync::atomic::{AtomicU64, Ordering};

use glam::DVec3;

/// Tetrahedra a scene may have unless raised (`softgrip --max-tetrahedra`): about 1 GiB.
pub const DEFAULT_MAX_TETRAHEDRA: u64 = 2_000_000;

/// What a tetrahedron costs a running simulation, mesh and model together (bytes): the 1.6 mm
/// built-in scene (79,872 tetrahedra) peaks at 40.3 MiB, the 4 mm one (4,320) at 6.2 MiB
/// (`docs/results/benchmarks.md`). A nearly incompressible continuum's factored volume term
/// (`solver::pressure`) adds at most 430 bytes, and only on meshes small enough to use it.
pub const BYTES_PER_TETRAHEDRON: f64 = 530.0;

static MAX_TETRAHEDRA: AtomicU64 = AtomicU64::new(DEFAULT_MAX_TETRAHEDRA);

/// The limit for this process (the command line sets it once, before any scene is read).
pub fn set_max_tetrahedra(n: u64) {
    MAX_TETRAHEDRA.store(n, Ordering::Relaxed);
}

/// The limit on a mesh's tetrahedra for this process ([`set_max_tetrahedra`]).
pub fn max_tetrahedra() -> u64 {
    MAX_TETRAHEDRA.load(Ordering::Relaxed)
}

/// Cells along a length `len` at edge `h`, as the built-in meshes divide it (`even`: an even
/// count, at least 2). In `f64`: a tiny `h` must not overflow before it is refused.
pub(super) fn cells(len: f64, h: f64, even: bool) -> f64 {
    let r = len / h;
    if even {
        (2.0 * (r / 2.0).round()).max(2.0)
    } else {
        r.round().max(1.0)
    }
}

/// Tetrahedra of the built-in cuboid (six a cell).
pub fn cuboid_tetrahedra(size: DVec3, h: f64) -> f64 {
    6.0 * cells(size.x, h, true) * cells(size.y, h, true) * cells(size.z, h, false)
}

/// Tetrahedra of the built-in cylinder (rings of 6 k triangles, three prisms' tetrahedra each,
/// in every layer).
pub fn cylinder_tetrahedra(radius: f64, height: f64, h: f64) -> f64 {
    let rings = cells(radius, h, false);
    18.0 * rings * rings * cells(height, h, false)
}

/// Fewest tetrahedra TetGen can fill `volume` (m^3) with at edge `h`: none larger than the
/// regular one (`tetrahedralize::max_volume`).
pub fn tetgen_tetrahedra_at_least(volume: f64, h: f64) -> f64 {
    volume.abs() / (h.powi(3) / (6.0 * std::f64::consts::SQRT_2))
}

/// The machine's memory (bytes), where the system says (`/proc/meminfo` on Linux).
pub fn memory_bytes() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let kib: f64 = text
        .lines()
        .find_map(|l| l.strip_prefix("MemTotal:"))?
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some(kib * 1024.0)
}

/// Why a mesh of `count` tetrahedra (at edge `h`, counted by `count_at`) is refused, with the
/// smallest edge that keeps within the limit, checked with `count_at` itself; `None` if it fits.
/// The limit is `softgrip --max-tetrahedra`, or what the machine's memory holds where that is
/// less (a limit raised to 2^64 - 1 once let 4.8 TB be asked for, and the process abort).
pub fn refusal(count: f64, h: f64, count_at: impl Fn(f64) -> f64) -> Option<Refusal> {
    refusal_within(count, h, count_at, max_tetrahedra(), memory_bytes())
}

fn refusal_within(
    count: f64,
    h: f64,
    count_at: impl Fn(f64) -> f64,
    max: u64,
    memory: Option<f64>,
) -> Option<Refusal> {
    let held = memory.map(|m| (m / BYTES_PER_TETRAHEDRON).floor());
    let (limit, by_memory) = match held {
        Some(m) if m < max as f64 => (m, true),
        _ => (max as f64, false),
    };
    if count.is_finite() && count <= limit {
        return None;
    }
    // The count goes as 1/h^3; rounding of cells can leave it just over: step up until under.
    let mut edge = if count.is_finite() && limit > 0.0 {
        h * (count / limit).cbrt()
    } else {
        h
    };
    // Even the coarsest mesh of the shape may be over a tiny limit: no edge then.
    let mut fits = false;
    if count_at(f64::INFINITY) <= limit {
        for _ in 0..2000 {
            if count_at(edge) <= limit {
                fits = true;
                break;
            }
            edge *= 1.01;
        }
    }
    Some(Refusal {
        count,
        gib: count * BYTES_PER_TETRAHEDRON / (1u64 << 30) as f64,
        limit: limit as u64,
        by_memory,
        memory_gib: memory.map(|m| m / (1u64 << 30) as f64),
        edge: fits
            .then(|| round_up(edge))
            .filter(|e| count_at(*e) <= limit),
        coarsest: count_at(f64::INFINITY),
    })
}

/// A mesh too large to build.
#[derive(Debug, Clone, PartialEq)]
pub struct Refusal {
    /// Tetrahedra the edge length would make (at least).
    pub count: f64,
    /// What they would take (GiB).
    pub gib: f64,
    /// Tetrahedra allowed: `--max-tetrahedra`, or what the memory holds where that is less.
    pub limit: u64,
    /// Whether the machine's memory set the limit.
    pub by_memory: bool,
    /// The machine's memory (GiB), where known.
    pub memory_gib: Option<f64>,
    /// The smallest edge length (m, two significant digits, rounded up) within the limit;
    /// `None` where even the coarsest mesh of the shape is over it.
    pub edge: Option<f64>,
    /// Tetrahedra of the coarsest mesh the shape can have.
    pub coarsest: f64,
}

/// `x` rounded up to two significant digits.
fn round_up(x: f64) -> f64 {
    if !(x.is_finite() && x > 0.0) {
        return x;
    }
    let scale = 10f64.powf(x.log10().floor() - 1.0);
    // Printed as typed: 5.6e-4, not 5.600000000000001e-4.
    let up = (x / scale).ceil() * scale;
    format!("{up:.1e}").parse().unwrap_or(up)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::TetMesh;

    #[test]
    fn the_counts_are_the_built_meshes() {
        for (size, h) in [
            (DVec3::new(0.05, 0.05, 0.02), 0.004),
            (DVec3::new(0.03, 0.02, 0.01), 0.005),
            (DVec3::splat(0.02), 0.0031),
        ] {
            let built = TetMesh::cuboid(size, h).tets.len();
            assert_eq!(cuboid_tetrahedra(size, h), built as f64, "{size} at {h}");
        }
        for (r, height, h) in [(0.04, 0.053, 0.004), (0.01, 0.03, 0.0025)] {
            let built = TetMesh::cylinder(r, height, h).tets.len();
            assert_eq!(cylinder_tetrahedra(r, height, h), built as f64);
        }
    }

    #[test]
    fn the_suggested_edge_keeps_within_the_limit() {
        let size = DVec3::new(0.05, 0.05, 0.02);
        let count_at = |h: f64| cuboid_tetrahedra(size, h);
        let memory = Some(64.0 * (1u64 << 30) as f64);
        let r = refusal_within(
            count_at(2e-4),
            2e-4,
            count_at,
            DEFAULT_MAX_TETRAHEDRA,
            memory,
        )
        .expect("37 M tetrahedra are refused");
        assert!(r.count > 3e7 && r.gib > 10.0 && !r.by_memory, "{r:?}");
        let edge = r.edge.expect("an edge within the limit");
        assert!(count_at(edge) <= DEFAULT_MAX_TETRAHEDRA as f64, "{r:?}");
        // ... and is not needlessly coarse: 10 % finer is over.
        assert!(
            count_at(0.9 * edge) > DEFAULT_MAX_TETRAHEDRA as f64,
            "{r:?}"
        );
        assert!(
            refusal_within(
                count_at(0.004),
                0.004,
                count_at,
                DEFAULT_MAX_TETRAHEDRA,
                memory
            )
            .is_none()
        );
        assert!((round_up(1.234e-4) - 1.3e-4).abs() < 1e-12);
    }

    #[test]
    fn a_limit_past_the_memory_is_held_to_what_the_memory_holds() {
        let size = DVec3::new(0.05, 0.05, 0.02);
        let count_at = |h: f64| cuboid_tetrahedra(size, h);
        let memory = Some(1.0 * (1u64 << 30) as f64);
        let r = refusal_within(count_at(1e-5), 1e-5, count_at, u64::MAX, memory)
            .expect("a trillion tetrahedra are refused whatever --max-tetrahedra says");
        assert!(r.by_memory, "{r:?}");
        assert!(r.limit as f64 * BYTES_PER_TETRAHEDRON <= (1u64 << 30) as f64);
        assert!(count_at(r.edge.expect("an edge that fits")) <= r.limit as f64);
    }

    #[test]
    fn no_edge_is_suggested_where_the_coarsest_mesh_is_over_the_limit() {
        let size = DVec3::new(0.05, 0.05, 0.02);
        let count_at = |h: f64| cuboid_tetrahedra(size, h);
        let r = refusal_within(count_at(0.004), 0.004, count_at, 10, None)
            .expect("4,320 tetrahedra over a limit of 10");
        assert_eq!(r.edge, None, "{r:?}");
        assert_eq!(r.coarsest, 24.0);
        assert!((round_up(5.31e-4) - 5.4e-4).abs() < 1e-12);
    }
}
