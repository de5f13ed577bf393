//! `lopin mesh info FILE.msh`: reads a Gmsh MSH 4.1 file (ASCII or binary, `lopin_core::mesh::msh`),
//! checks every element, and prints what Lopin sees: nodes, cells and facets by type, the
//! bounding box, and each physical group with its element count and volume or area (`--json`:
//! the same as one object). A file Lopin cannot use is an error naming it and the reason.
//! `lopin mesh granular` lives in [`super::mesh_granular`].

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Subcommand};
use lopin_core::mesh::msh::{self, MshMesh};
use lopin_core::mesh::{bounding_box_of, Element};
use serde::Serialize;

use super::report::column_table;

#[derive(Debug, Subcommand)]
pub enum MeshCommand {
    /// Read an MSH 4.1 file and print its nodes, elements and physical groups.
    Info(InfoArgs),
    /// Generate the polyhedral granular sample of a [granular_poly] scene and mesh it with gmsh.
    Granular(super::mesh_granular::GranularArgs),
}

#[derive(Debug, Args)]
pub struct InfoArgs {
    /// The .msh file.
    pub file: PathBuf,
    /// Print one JSON object instead of the tables.
    #[arg(long)]
    pub json: bool,
}

/// One physical group as reported.
#[derive(Debug, Serialize)]
struct Group {
    dim: i32,
    tag: i32,
    name: String,
    elements: usize,
    /// Volume (m³) of a volume group, area (m²) of a surface group.
    measure: f64,
}

/// The report.
#[derive(Debug, Serialize)]
struct Info {
    file: String,
    nodes: usize,
    tetrahedra: usize,
    hexahedra: usize,
    surface_facets: usize,
    bounding_box: [[f64; 3]; 2],
    physicals: Vec<Group>,
}

fn info_of(m: &MshMesh) -> anyhow::Result<Info> {
    let mut physicals = Vec::new();
    for p in &m.physicals {
        let (elements, measure) = match p.dim {
            3 => {
                let cells = m.volume_cells(&p.name)?;
                (cells.len(), m.volume_of(&cells))
            }
            2 => {
                let facets = m.surface_facets(&p.name)?;
                (facets.len(), m.area_of(&facets))
            }
            _ => (0, 0.0),
        };
        physicals.push(Group {
            dim: p.dim,
            tag: p.tag,
            name: p.name.clone(),
            elements,
            measure,
        });
    }
    let (lo, hi) = bounding_box_of(&m.nodes);
    let tetrahedra = m
        .cells
        .iter()
        .filter(|c| matches!(c.nodes, Element::Tet4(_)))
        .count();
    Ok(Info {
        file: m.source.clone(),
        nodes: m.nodes.len(),
        tetrahedra,
        hexahedra: m.cells.len() - tetrahedra,
        surface_facets: m.facets.len(),
        bounding_box: [lo, hi],
        physicals,
    })
}

pub fn mesh(cmd: &MeshCommand) -> anyhow::Result<ExitCode> {
    match cmd {
        MeshCommand::Granular(args) => super::mesh_granular::granular(args),
        MeshCommand::Info(args) => {
            let m = msh::read(&args.file)?;
            let info = info_of(&m)?;
            if args.json {
                println!("{}", serde_json::to_string_pretty(&info)?);
                return Ok(ExitCode::SUCCESS);
            }
            println!(
                "{}: {} nodes, {} tetrahedra, {} hexahedra, {} surface facets",
                info.file, info.nodes, info.tetrahedra, info.hexahedra, info.surface_facets
            );
            let [lo, hi] = info.bounding_box;
            println!(
                "bounding box: [{:.4e}, {:.4e}] x [{:.4e}, {:.4e}] x [{:.4e}, {:.4e}] m",
                lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]
            );
            let mut t = column_table(["physical group", "dim", "tag", "elements", "volume / area"]);
            for g in &info.physicals {
                let unit = if g.dim == 3 { "m³" } else { "m²" };
                t.add_row([
                    g.name.clone(),
                    g.dim.to_string(),
                    g.tag.to_string(),
                    g.elements.to_string(),
                    format!("{:.6e} {unit}", g.measure),
                ]);
            }
            println!("{t}");
            Ok(ExitCode::SUCCESS)
        }
    }
}
