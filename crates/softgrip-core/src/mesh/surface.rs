//! Closed triangle surfaces (`.stl` ASCII or binary, `.obj`) and their
//! checks before tetrahedralization: welded vertices, every edge shared by
//! exactly two triangles in opposite directions (closed, consistently
//! oriented), outward orientation (positive enclosed volume), no two
//! triangles crossing. Each failure names the problem and where.

use std::collections::HashMap;

use glam::DVec3;

use super::io::cursor::Cursor;
use super::io::error::ImportError;

/// A triangle surface: welded vertices and triangles wound (ideally)
/// counter-clockwise seen from outside.
#[derive(Debug, Clone, PartialEq)]
pub struct Surface {
    /// Vertex positions: the file's units as read, m once scaled (length: vertices).
    pub vertices: Vec<DVec3>,
    /// Triangles as three indices into `vertices` (length: triangles).
    pub triangles: Vec<[u32; 3]>,
}

impl Surface {
    /// Enclosed volume by the divergence theorem (m^3); negative when the
    /// triangles face inward.
    pub fn volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.vertices[i as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    /// Mean edge length (m).
    pub fn mean_edge(&self) -> f64 {
        let mut sum = 0.0;
        for t in &self.triangles {
            let p = t.map(|i| self.vertices[i as usize]);
            sum += p[0].distance(p[1]) + p[1].distance(p[2]) + p[2].distance(p[0]);
        }
        sum / (3 * self.triangles.len().max(1)) as f64
    }
}

/// Reads `.stl` (ASCII or binary) or `.obj`.
pub fn read(bytes: &[u8], name: &str, obj: bool) -> Result<Surface, ImportError> {
    let soup = if obj {
        read_obj(bytes, name)?
    } else if is_binary_stl(bytes) {
        read_binary_stl(bytes, name)?
    } else {
        read_ascii_stl(bytes, name)?
    };
    Ok(weld(&soup))
}

/// A binary STL has exactly 84 + 50 n bytes for the n in its header
/// (ASCII files also start with "solid", and some binary ones too).
fn is_binary_stl(bytes: &[u8]) -> bool {
    if bytes.len() < 84 {
        return !bytes.trim_ascii_start().starts_with(b"solid");
    }
    let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
    n.checked_mul(50).and_then(|b| b.checked_add(84)) == Some(bytes.len())
}

fn read_binary_stl(bytes: &[u8], name: &str) -> Result<Vec<[DVec3; 3]>, ImportError> {
    if bytes.len() < 84 {
        return Err(ImportError::at(
            name,
            None,
            format!(
                "{} bytes: too short for a binary STL (84-byte header) and not ASCII STL (\"solid ...\")",
                bytes.len()
            ),
        ));
    }
    let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
    if Some(bytes.len()) != n.checked_mul(50).and_then(|b| b.checked_add(84)) {
        return Err(ImportError::at(
            name,
            None,
            format!(
                "the binary STL header announces {n} triangles ({} bytes), the file has {} bytes (truncated or not STL)",
                84 + 50 * n as u64,
                bytes.len()
            ),
        ));
    }
    let mut out = Vec::with_capacity(n);
    for k in 0..n {
        let base = 84 + 50 * k + 12;
        let mut tri = [DVec3::ZERO; 3];
        for (v, slot) in tri.iter_mut().enumerate() {
            let f = |i: usize| {
                let at = base + 12 * v + 4 * i;
                f64::from(f32::from_le_bytes([
                    bytes[at],
                    bytes[at + 1],
                    bytes[at + 2],
                    bytes[at + 3],
                ]))
            };
            *slot = DVec3::new(f(0), f(1), f(2));
            if !slot.is_finite() {
                return Err(ImportError::at(
                    name,
                    None,
                    format!("triangle {} has a non-finite vertex {slot}", k + 1),
                ));
            }
        }
        out.push(tri);
    }
    Ok(out)
}

fn read_ascii_stl(bytes: &[u8], name: &str) -> Result<Vec<[DVec3; 3]>, ImportError> {
    let mut c = Cursor::new(bytes, name);
    if c.at_end() {
        return Err(c.error("the file is empty"));
    }
    let first = c.expect_token("solid")?;
    if first != "solid" {
        let n = bytes
            .get(80..84)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
        return Err(ImportError::at(
            name,
            None,
            format!(
                "not an STL file: neither a binary STL (its header announces {} triangles, {} bytes, but the file has {}) nor an ASCII one (it does not start with \"solid\")",
                n.map_or("no".to_string(), |n| n.to_string()),
                n.map_or("84+".to_string(), |n| (84 + 50 * u64::from(n)).to_string()),
                bytes.len()
            ),
        ));
    }
    c.rest_of_line();
    let mut out = Vec::new();
    loop {
        let t = c.expect_token("facet or endsolid")?;
        match t {
            "endsolid" => break,
            "facet" => {
                c.expect_keyword("normal")?;
                for _ in 0..3 {
                    c.f64("a normal component")?;
                }
                c.expect_keyword("outer")?;
                c.expect_keyword("loop")?;
                let mut tri = [DVec3::ZERO; 3];
                for v in &mut tri {
                    c.expect_keyword("vertex")?;
                    *v = DVec3::new(
                        c.f64("an x coordinate")?,
                        c.f64("a y coordinate")?,
                        c.f64("a z coordinate")?,
                    );
                }
                c.expect_keyword("endloop")?;
                c.expect_keyword("endfacet")?;
                out.push(tri);
            }
            other => {
                return Err(c.error(format!("expected facet or endsolid, found {other:?}")));
            }
        }
    }
    Ok(out)
}

/// OBJ: `v x y z` and `f a b c ...` (polygons fanned into triangles,
/// `a/t/n` references and negative indices allowed); other lines ignored.
fn read_obj(bytes: &[u8], name: &str) -> Result<Vec<[DVec3; 3]>, ImportError> {
    let text = String::from_utf8_lossy(bytes);
    let mut vertices = Vec::new();
    let mut out = Vec::new();
    for (k, line) in text.lines().enumerate() {
        let err = |m: String| ImportError::at(name, Some(k + 1), m);
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let mut p = [0.0; 3];
                for (i, slot) in p.iter_mut().enumerate() {
                    let w = words
                        .next()
                        .ok_or_else(|| err(format!("a vertex with {i} coordinates")))?;
                    *slot = w
                        .parse::<f64>()
                        .ok()
                        .filter(|v| v.is_finite())
                        .ok_or_else(|| err(format!("{w:?} is not a finite coordinate")))?;
                }
                vertices.push(DVec3::from_array(p));
            }
            Some("f") => {
                let mut face = Vec::new();
                for w in words {
                    let index = w.split('/').next().unwrap_or("");
                    let i: i64 = index
                        .parse()
                        .map_err(|_| err(format!("{w:?} is not a vertex reference")))?;
                    let resolved = if i > 0 {
                        i - 1
                    } else {
                        vertices.len() as i64 + i
                    };
                    if resolved < 0 || resolved >= vertices.len() as i64 {
                        return Err(err(format!(
                            "face refers to vertex {i}, but {} vertices are defined so far",
                            vertices.len()
                        )));
                    }
                    face.push(vertices[resolved as usize]);
                }
                if face.len() < 3 {
                    return Err(err(format!("a face with {} vertices", face.len())));
                }
                for k in 1..face.len() - 1 {
                    out.push([face[0], face[k], face[k + 1]]);
                }
            }
            _ => {}
        }
    }
    if out.is_empty() {
        return Err(ImportError::at(name, None, "no faces (f lines)"));
    }
    Ok(out)
}

/// Merges bit-identical vertices (STL repeats them per triangle).
fn weld(soup: &[[DVec3; 3]]) -> Surface {
    let mut index: HashMap<[u64; 3], u32> = HashMap::new();
    let mut vertices = Vec::new();
    let triangles = soup
        .iter()
        .map(|tri| {
            tri.map(|p| {
                let key = p.to_array().map(|c| (c + 0.0).to_bits());
                *index.entry(key).or_insert_with(|| {
                    vertices.push(p);
                    (vertices.len() - 1) as u32
                })
            })
        })
        .collect();
    Surface {
        vertices,
        triangles,
    }
}

/// The problems that keep a surface from being tetrahedralized.
pub fn check(s: &Surface, name: &str) -> Result<(), ImportError> {
    let err = |m: String| ImportError::at(name, None, m);
    check_triangles(s).map_err(err)?;
    check_edges(s).map_err(err)?;
    let v = s.volume();
    if v <= 0.0 {
        return Err(err(format!(
            "the surface is inside out: its triangles face inward (enclosed volume {v:.4e} m^3); reverse their winding"
        )));
    }
    if let Some((i, j, at)) = first_crossing(s) {
        return Err(err(format!(
            "the surface intersects itself: triangles {} and {} cross near {}",
            i + 1,
            j + 1,
            fmt_point(at)
        )));
    }
    Ok(())
}

/// At least four triangles, none degenerate (a repeated vertex or zero area).
fn check_triangles(s: &Surface) -> Result<(), String> {
    if s.triangles.len() < 4 {
        return Err(format!(
            "{} triangles cannot close a volume",
            s.triangles.len()
        ));
    }
    for (k, t) in s.triangles.iter().enumerate() {
        let p = t.map(|i| s.vertices[i as usize]);
        if t[0] == t[1]
            || t[1] == t[2]
            || t[0] == t[2]
            || (p[1] - p[0]).cross(p[2] - p[0]) == DVec3::ZERO
        {
            return Err(format!(
                "triangle {} is degenerate (zero area) at {}",
                k + 1,
                fmt_point(p[0])
            ));
        }
    }
    Ok(())
}

/// Closed, manifold and consistently oriented: every edge walked once each way.
fn check_edges(s: &Surface) -> Result<(), String> {
    // Each undirected edge: how often it is walked each way. A closed,
    // consistently oriented surface walks every edge once each way.
    let mut uses: HashMap<(u32, u32), (u32, u32)> = HashMap::new();
    for t in &s.triangles {
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            let entry = uses.entry((a.min(b), a.max(b))).or_insert((0, 0));
            if a < b {
                entry.0 += 1;
            } else {
                entry.1 += 1;
            }
        }
    }
    let mut open = Vec::new();
    let mut flipped = Vec::new();
    let mut shared = Vec::new();
    for (&edge, &(forward, backward)) in &uses {
        match forward + backward {
            1 => open.push(edge),
            2 if forward != 1 => flipped.push(edge),
            2 => {}
            _ => shared.push(edge),
        }
    }
    let near = |edges: &mut Vec<(u32, u32)>| {
        edges.sort_unstable();
        let (a, b) = edges[0];
        fmt_point(0.5 * (s.vertices[a as usize] + s.vertices[b as usize]))
    };
    if !open.is_empty() {
        return Err(format!(
            "the surface is not closed: {} open edges near {} (fill the hole)",
            open.len(),
            near(&mut open)
        ));
    }
    if !shared.is_empty() {
        return Err(format!(
            "{} edges are shared by more than two triangles (not a manifold surface), e.g. near {}",
            shared.len(),
            near(&mut shared)
        ));
    }
    if !flipped.is_empty() {
        return Err(format!(
            "the triangles are not consistently oriented: {} edges are walked the same way by both their triangles, e.g. near {} (flip the odd triangles)",
            flipped.len(),
            near(&mut flipped)
        ));
    }
    Ok(())
}

fn fmt_point(p: DVec3) -> String {
    format!("({:.4}, {:.4}, {:.4}) m", p.x, p.y, p.z)
}

/// The first pair of triangles that cross (an edge of one passes through
/// the other), with a grid as broad phase; pairs sharing an edge are
/// skipped, pairs sharing a vertex test only the edges away from it.
fn first_crossing(s: &Surface) -> Option<(usize, usize, DVec3)> {
    let cell = s.mean_edge().max(1e-12);
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    let boxes: Vec<(DVec3, DVec3)> = s
        .triangles
        .iter()
        .map(|t| {
            let p = t.map(|i| s.vertices[i as usize]);
            (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]))
        })
        .collect();
    // A triangle over many cells (a cube's face beside fine detail) is tested against every
    // other whose box meets its own, outside the grid.
    let mut large = Vec::new();
    for (k, (lo, hi)) in boxes.iter().enumerate() {
        let a = (*lo / cell).floor().as_i64vec3();
        let b = (*hi / cell).floor().as_i64vec3();
        if (b - a).max_element() > 64 {
            large.push(k);
            continue;
        }
        for x in a.x..=b.x {
            for y in a.y..=b.y {
                for z in a.z..=b.z {
                    grid.entry([x, y, z]).or_default().push(k as u32);
                }
            }
        }
    }
    for &i in &large {
        for j in 0..s.triangles.len() {
            let (bi, bj) = (boxes[i], boxes[j]);
            if i == j || bi.0.cmpgt(bj.1).any() || bj.0.cmpgt(bi.1).any() {
                continue;
            }
            if let Some(at) = crossing(s, i.min(j), i.max(j)) {
                return Some((i.min(j), i.max(j), at));
            }
        }
    }
    let mut keys: Vec<&[i64; 3]> = grid.keys().collect();
    keys.sort_unstable();
    for key in keys {
        let list = &grid[key];
        for (n, &i) in list.iter().enumerate() {
            for &j in &list[n + 1..] {
                let (i, j) = (i.min(j) as usize, i.max(j) as usize);
                let (bi, bj) = (boxes[i], boxes[j]);
                if bi.0.cmpgt(bj.1).any() || bj.0.cmpgt(bi.1).any() {
                    continue;
                }
                if let Some(at) = crossing(s, i, j) {
                    return Some((i, j, at));
                }
            }
        }
    }
    None
}

fn crossing(s: &Surface, i: usize, j: usize) -> Option<DVec3> {
    let (ti, tj) = (s.triangles[i], s.triangles[j]);
    let shared = ti.iter().filter(|v| tj.contains(v)).count();
    if shared >= 2 {
        return None;
    }
    let pi = ti.map(|v| s.vertices[v as usize]);
    let pj = tj.map(|v| s.vertices[v as usize]);
    let edges = |t: [u32; 3], p: [DVec3; 3], other: [u32; 3]| {
        (0..3)
            .filter(move |&e| !(other.contains(&t[e]) || other.contains(&t[(e + 1) % 3])))
            .map(move |e| (p[e], p[(e + 1) % 3]))
    };
    for (a, b) in edges(ti, pi, tj) {
        if let Some(x) = segment_hits(a, b, pj) {
            return Some(x);
        }
    }
    for (a, b) in edges(tj, pj, ti) {
        if let Some(x) = segment_hits(a, b, pi) {
            return Some(x);
        }
    }
    None
}

/// Where segment `a b` meets triangle `t`, its edges included (to a relative 1e-9): a segment
/// through the diagonal two triangles share hits both on their boundary, and a strict test
/// missed it (two overlapping cubes passed as not self-intersecting).
fn segment_hits(a: DVec3, b: DVec3, t: [DVec3; 3]) -> Option<DVec3> {
    let d = b - a;
    let e1 = t[1] - t[0];
    let e2 = t[2] - t[0];
    let h = d.cross(e2);
    let det = e1.dot(h);
    let scale = e1.length() * e2.length() * d.length();
    if det.abs() <= 1e-12 * scale {
        return None;
    }
    let s = a - t[0];
    let u = s.dot(h) / det;
    let q = s.cross(e1);
    let v = d.dot(q) / det;
    let w = e2.dot(q) / det;
    let eps = 1e-9;
    (u >= -eps && v >= -eps && u + v <= 1.0 + eps && w >= -eps && w <= 1.0 + eps).then(|| a + w * d)
}
