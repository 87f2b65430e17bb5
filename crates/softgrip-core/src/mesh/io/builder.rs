//! What the readers share: nodes and tetrahedra collected by their file tags, and the result.

use std::collections::{BTreeMap, HashMap};

use glam::DVec3;

use crate::mesh::TetMesh;

/// What a reader produced: the tetrahedra as written (not yet checked or
/// repaired: see [`crate::mesh::checks`]) and what it skipped.
#[derive(Debug, Clone, PartialEq)]
pub struct Imported {
    /// The nodes in the file's order and units, and the tetrahedra by their index.
    pub mesh: TetMesh,
    /// What the reader noted (corner nodes only, cells skipped by kind), one sentence each.
    pub warnings: Vec<String>,
}

/// Collects nodes by their file tags and tetrahedra by node tags, and
/// counts the cells it skips.
#[derive(Debug, Default)]
pub(super) struct Builder {
    pub(super) nodes: Vec<DVec3>,
    pub(super) index: HashMap<i64, u32>,
    pub(super) tets: Vec<[i64; 4]>,
    pub(super) skipped: BTreeMap<String, usize>,
    pub(super) notes: Vec<String>,
}

impl Builder {
    pub(super) fn node(&mut self, tag: i64, p: DVec3) -> Result<(), String> {
        if self.index.insert(tag, self.nodes.len() as u32).is_some() {
            return Err(format!("node {tag} is defined twice"));
        }
        self.nodes.push(p);
        Ok(())
    }

    pub(super) fn skip(&mut self, kind: &str) {
        *self.skipped.entry(kind.to_string()).or_insert(0) += 1;
    }

    /// The mesh, each tetrahedron's tags resolved; the first unknown tag is
    /// an error (the caller names the file).
    pub(super) fn finish(self) -> Result<Imported, String> {
        let mut tets = Vec::with_capacity(self.tets.len());
        for (k, t) in self.tets.iter().enumerate() {
            let mut tet = [0u32; 4];
            for (slot, tag) in tet.iter_mut().zip(t) {
                *slot = *self.index.get(tag).ok_or_else(|| {
                    format!(
                        "tetrahedron {} refers to node {tag}, which the file does not define",
                        k + 1
                    )
                })?;
            }
            tets.push(tet);
        }
        if tets.is_empty() {
            let other = if self.skipped.is_empty() {
                String::from("no cells at all")
            } else {
                self.skipped
                    .iter()
                    .map(|(k, n)| format!("{n} {k}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            return Err(format!(
                "the file has no tetrahedra ({other}); softgrip needs a volume mesh (a closed surface is tetrahedralized only from .stl or .obj)"
            ));
        }
        let mut warnings = self.notes;
        if !self.skipped.is_empty() {
            let list = self
                .skipped
                .iter()
                .map(|(k, n)| format!("{n} {k}"))
                .collect::<Vec<_>>()
                .join(", ");
            warnings.push(format!("skipped cells that are not tetrahedra: {list}"));
        }
        Ok(Imported {
            mesh: TetMesh {
                nodes: self.nodes,
                tets,
            },
            warnings,
        })
    }
}
