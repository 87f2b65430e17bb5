//! `softgrip mesh`: a mesh file's figures and checks, its conversion to
//! another format, and the mesh a scene uses written out.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use softgrip_core::mesh::{TetMesh, checks, io};
use softgrip_core::scene::Scene;
use softgrip_lab::json::commands::{MeshFigures, SurfaceFigures, TetMeshFigures};

/// Mesh files: figures, conversion, and the mesh a scene uses.
#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    action: Action,
}

#[derive(clap::Subcommand)]
enum Action {
    /// Nodes, tetrahedra, boundary facets, volume, bounds, edge lengths,
    /// smallest dihedral angle, worst aspect ratio, parts; and what the
    /// checks would change.
    Info {
        file: PathBuf,
        /// Also write the figures as JSON here (a tetrahedral mesh's after the checks).
        #[arg(long)]
        json: Option<PathBuf>,
    },
    /// Convert between formats (.msh, .node/.ele, .vtk, .vtu); the output's
    /// extension picks the format unless --format says (msh22 for Gmsh 2.2).
    Convert {
        input: PathBuf,
        output: PathBuf,
        #[arg(long, value_enum)]
        format: Option<super::values::MeshFormat>,
    },
    /// Write the mesh a scene uses (built-in shapes meshed at their edge
    /// length; mesh files checked, scaled and placed).
    Make {
        scene: PathBuf,
        output: PathBuf,
        #[arg(long, value_enum)]
        format: Option<super::values::MeshFormat>,
    },
}

/// The files a mesh path stands for: a TetGen mesh is a `.node` and an `.ele` (and a `.face`).
fn mesh_files(path: &Path) -> Vec<PathBuf> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    if ["node", "ele", "face"]
        .iter()
        .any(|e| ext.eq_ignore_ascii_case(e))
    {
        ["node", "ele", "face"]
            .iter()
            .map(|e| path.with_extension(e))
            .collect()
    } else {
        vec![path.to_path_buf()]
    }
}

/// Refuses an output over an input, or one that cannot be written, before any work.
fn check_outputs(inputs: &[&Path], outputs: &[(&str, Option<&Path>)]) -> Result<()> {
    let mut o = super::outputs::Outputs::new();
    for i in inputs {
        for f in mesh_files(i) {
            o = o.input(&f);
        }
    }
    for (option, path) in outputs {
        for f in path.map(mesh_files).unwrap_or_default() {
            // A TetGen output writes no .face.
            if f.extension().is_some_and(|e| e == "face") {
                continue;
            }
            o = o.file(option, Some(&f));
        }
    }
    o.check()
}

pub fn run(args: Args) -> Result<()> {
    match &args.action {
        Action::Info { file, json } => check_outputs(&[file], &[("--json", json.as_deref())])?,
        Action::Convert { input, output, .. } => {
            check_outputs(&[input], &[("the output", Some(output))])?
        }
        Action::Make { scene, output, .. } => {
            let mut inputs = vec![scene.as_path()];
            let loaded = Scene::load(scene).ok();
            if let Some(softgrip_core::scene::Shape::Mesh { path, .. }) =
                loaded.as_ref().map(|s| &s.object.shape)
            {
                inputs.push(path);
            }
            check_outputs(&inputs, &[("the output", Some(output))])?
        }
    }
    match args.action {
        Action::Info { file, json } if io::is_surface(&file) => {
            info_surface(&file, json.as_deref())
        }
        Action::Info { file, json } => info_tets(&file, json.as_deref()),
        Action::Convert {
            input,
            output,
            format,
        } => convert(&input, &output, format.map(|f| f.0)),
        Action::Make {
            scene,
            output,
            format,
        } => make(&scene, &output, format.map(|f| f.0)),
    }
}

/// A closed surface (.stl, .obj): its figures and checks.
fn info_surface(file: &Path, json: Option<&Path>) -> Result<()> {
    let surface = softgrip_core::mesh::surface::read(
        &softgrip_core::files::read_at_most(file, io::MAX_MESH_BYTES)
            .with_context(|| format!("reading {}", file.display()))?,
        &file.display().to_string(),
        file.extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("obj")),
    )?;
    println!(
        "{} (a surface: tetrahedralized when a scene uses it)",
        file.display()
    );
    println!("  triangles: {}", surface.triangles.len());
    println!("  vertices (welded): {}", surface.vertices.len());
    println!("  enclosed volume: {:.6e} m^3", surface.volume());
    println!("  mean edge: {:.3} mm", 1e3 * surface.mean_edge());
    softgrip_core::mesh::surface::check(&surface, &file.display().to_string())?;
    println!("  closed, consistently oriented, outward, not self-intersecting");
    if let Some(path) = json {
        let figures = MeshFigures::Surface(SurfaceFigures {
            file: file.display().to_string(),
            surface: true,
            triangles: surface.triangles.len(),
            vertices: surface.vertices.len(),
            volume_m3: surface.volume(),
            mean_edge_m: surface.mean_edge(),
        });
        super::figures::write_json_line(path, &serde_json::to_value(&figures)?)?;
    }
    Ok(())
}

/// A tetrahedral mesh: its figures as written and after the checks.
fn info_tets(file: &Path, json: Option<&Path>) -> Result<()> {
    let imported = io::read(file)?;
    let raw = &imported.mesh;
    println!("{}", file.display());
    println!(
        "  as written: {} nodes, {} tetrahedra",
        raw.nodes.len(),
        raw.tets.len()
    );
    for w in &imported.warnings {
        println!("  note: {w}");
    }
    let mut mesh = imported.mesh.clone();
    let report = checks::repair(&mut mesh)
        .with_context(|| format!("{}: the mesh cannot be used", file.display()))?;
    for w in &report.warnings {
        println!("  check: {w}");
    }
    let stats = mesh.stats();
    let (lo, hi) = mesh.bounds();
    let (angle, aspect) = checks::shape_figures(&mesh);
    println!("  nodes: {}", stats.nodes);
    println!("  tetrahedra: {}", stats.tets);
    println!("  boundary facets: {}", stats.boundary_facets);
    println!("  volume: {:.6e} m^3", stats.volume);
    println!(
        "  bounds: ({:.4}, {:.4}, {:.4}) .. ({:.4}, {:.4}, {:.4}) m, size {:.4} x {:.4} x {:.4} m",
        lo.x,
        lo.y,
        lo.z,
        hi.x,
        hi.y,
        hi.z,
        hi.x - lo.x,
        hi.y - lo.y,
        hi.z - lo.z
    );
    println!(
        "  edges: {:.3} .. {:.3} mm",
        1e3 * stats.min_edge,
        1e3 * stats.max_edge
    );
    println!("  smallest dihedral angle: {angle:.2} degrees");
    println!("  worst aspect ratio (longest edge / smallest height): {aspect:.2}");
    println!("  connected parts: {}", report.parts);
    if let Some(path) = json {
        let figures = MeshFigures::Tetrahedra(TetMeshFigures {
            file: file.display().to_string(),
            nodes: stats.nodes,
            tetrahedra: stats.tets,
            boundary_facets: stats.boundary_facets,
            volume_m3: stats.volume,
            bounds_m: [lo.to_array(), hi.to_array()],
            min_edge_m: stats.min_edge,
            max_edge_m: stats.max_edge,
            smallest_dihedral_deg: angle,
            worst_aspect_ratio: aspect,
            connected_parts: report.parts,
            warnings: imported
                .warnings
                .iter()
                .chain(&report.warnings)
                .cloned()
                .collect(),
        });
        super::figures::write_json_line(path, &serde_json::to_value(&figures)?)?;
    }
    Ok(())
}

fn convert(input: &Path, output: &Path, format: Option<io::Format>) -> Result<()> {
    if io::is_surface(input) {
        anyhow::bail!(
            "{}: a surface (triangles), not tetrahedra: `mesh convert` converts tetrahedral meshes. To fill it with tetrahedra, name it in a scene ([object] shape = \"mesh\", path = \"{}\", edge_length = ...) and run `softgrip mesh make SCENE {}` (TetGen: docs/meshes.md)",
            input.display(),
            input.display(),
            output.display()
        );
    }
    let format = format_for(output, format)?;
    let imported = io::read(input)?;
    for w in &imported.warnings {
        eprintln!("warning: {}: {w}", input.display());
    }
    let mut mesh = imported.mesh;
    let report = checks::repair(&mut mesh)
        .with_context(|| format!("{}: the mesh cannot be used", input.display()))?;
    for w in &report.warnings {
        eprintln!("warning: {}: {w}", input.display());
    }
    let written = write(&mesh, output, format)?;
    say_written(&written);
    Ok(())
}

fn make(scene: &Path, output: &Path, format: Option<io::Format>) -> Result<()> {
    let format = format_for(output, format)?;
    let scene = Scene::load(scene)?;
    let (mesh, warnings) = softgrip_core::Model::load_mesh(&scene)?;
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    let written = write(&mesh, output, format)?;
    println!("{}", mesh.stats());
    say_written(&written);
    Ok(())
}

/// `--format`, or the one the output's extension names.
fn format_for(path: &Path, format: Option<io::Format>) -> Result<io::Format> {
    format.or_else(|| io::Format::of(path)).with_context(|| {
        format!(
            "{}: give a .msh, .node, .ele, .vtk or .vtu name, or --format",
            path.display()
        )
    })
}

fn write(mesh: &TetMesh, output: &Path, format: io::Format) -> Result<Vec<PathBuf>> {
    io::write(mesh, output, format).with_context(|| format!("writing {}", output.display()))
}

fn say_written(written: &[PathBuf]) {
    for p in written {
        println!("wrote {}", p.display());
    }
}
