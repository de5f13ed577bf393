//! `lopin mesh granular [SCENE]`: the polyhedral granular sample of a scene's `[granular_poly]`
//! table (default `granular-poly`), with its grain count, seed and mesh size overridable:
//! places the grains, meshes the sample with gmsh (or takes it from the cache) and prints its
//! sizes and where the mesh lies; `--output` copies the .msh, `--geo` writes the gmsh script.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::Args;
use lopin_core::mesh::Element;
use lopin_core::scene;
use serde::Serialize;

#[derive(Debug, Args)]
pub struct GranularArgs {
    /// A built-in scene or scene file with a [granular_poly] table.
    #[arg(default_value = "granular-poly")]
    pub scene: String,
    /// Number of grains (overrides the table).
    #[arg(long)]
    pub grains: Option<usize>,
    /// Seed of the grain shapes and placement (overrides the table).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Tetrahedron size in m (overrides the table).
    #[arg(long)]
    pub mesh_size: Option<f64>,
    /// Copy the mesh to this .msh file.
    #[arg(long, short)]
    pub output: Option<PathBuf>,
    /// Write the gmsh script to this .geo file.
    #[arg(long)]
    pub geo: Option<PathBuf>,
    /// Print one JSON object instead of the lines.
    #[arg(long)]
    pub json: bool,
}

/// The report.
#[derive(Debug, Serialize)]
struct Sample {
    scene: String,
    grains: usize,
    grain_volume_fraction: f64,
    nodes: usize,
    tetrahedra: usize,
    cached: bool,
    mesh_seconds: f64,
    mesh: String,
}

pub fn granular(args: &GranularArgs) -> anyhow::Result<ExitCode> {
    let mut spec = scene::load(&args.scene)?;
    let source = scene::source_label(&args.scene);
    let Some(g) = spec.granular_poly.as_mut() else {
        anyhow::bail!("{source}: the scene has no [granular_poly] table");
    };
    if let Some(n) = args.grains {
        g.grains = n;
    }
    if let Some(s) = args.seed {
        g.seed = s;
    }
    if let Some(h) = args.mesh_size {
        g.mesh_size = h;
    }
    let grains = scene::granular_poly::placed_grains(&spec, &source)?;
    let g = spec.granular_poly.as_ref().expect("checked above");
    let script = g.script(&grains);
    if let Some(path) = &args.geo {
        std::fs::write(path, &script)
            .map_err(|e| anyhow::anyhow!("{}: cannot write: {e}", path.display()))?;
    }
    let cached = lopin_core::mesh::gmsh::is_cached(&spec.name, &script);
    let start = Instant::now();
    let file = lopin_core::mesh::gmsh::mesh_script(&spec.name, &script)?;
    let mesh_seconds = start.elapsed().as_secs_f64();
    let m = lopin_core::mesh::msh::read(&file)?;
    if let Some(path) = &args.output {
        std::fs::copy(&file, path)
            .map_err(|e| anyhow::anyhow!("{}: cannot write: {e}", path.display()))?;
    }
    let grain_volume: f64 = grains.iter().map(|p| p.volume()).sum();
    let sample = Sample {
        scene: spec.name.clone(),
        grains: grains.len(),
        grain_volume_fraction: grain_volume / g.side.powi(3),
        nodes: m.nodes.len(),
        tetrahedra: m
            .cells
            .iter()
            .filter(|c| matches!(c.nodes, Element::Tet4(_)))
            .count(),
        cached,
        mesh_seconds,
        mesh: args.output.as_ref().unwrap_or(&file).display().to_string(),
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&sample)?);
    } else {
        println!(
            "{}: {} grains ({:.1} % of the cube), {} nodes, {} tetrahedra; {} in {:.2} s",
            sample.scene,
            sample.grains,
            100.0 * sample.grain_volume_fraction,
            sample.nodes,
            sample.tetrahedra,
            if cached {
                "taken from the cache"
            } else {
                "meshed by gmsh"
            },
            sample.mesh_seconds
        );
        println!("mesh: {}", sample.mesh);
        if let Some(path) = &args.geo {
            println!("gmsh script: {}", path.display());
        }
    }
    Ok(ExitCode::SUCCESS)
}
