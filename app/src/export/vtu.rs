//! One substructure at one time step as a VTK XML unstructured grid (.vtu, written by the vtkio
//! crate): linear hexahedra and tetrahedra (Lopin's Hex8 and Tet4 node orders are VTK_HEXAHEDRON's and VTK_TETRA's), point data
//! `displacement`, `velocity` and `velocity_avg` (m, m/s; the step average (v_m + v_{m−1})/2,
//! which the undamped rule's alternating mode v_m = (−1)^m c does not reach: the velocity to look
//! at when a solve was stopped at a loose η, METHOD §10), cell data `von_mises` (Pa), `stress` (Cauchy tensor
//! at the element centre, 9 components, Pa; METHOD §2 Hex8), `substructure` and `material` ids.

use anyhow::Context;
use lopin_core::elements::hex8;
use lopin_core::mesh::Element;
use lopin_core::post::{self, SubFields};
use lopin_core::Solver;
use std::path::Path;
use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataArray, DataSet, UnstructuredGridPiece,
    Version, VertexNumbers, Vtk,
};

/// Point and cell field names, in file order.
pub const POINT_FIELDS: [&str; 3] = ["displacement", "velocity", "velocity_avg"];
/// Cell field names, in file order.
pub const CELL_FIELDS: [&str; 4] = ["von_mises", "stress", "substructure", "material"];

/// The grid of substructure `i` with fields `f` and the fields `prev` of the step before (the
/// same fields at m = 0).
pub fn grid(solver: &Solver, i: usize, f: &SubFields, prev: &SubFields, title: String) -> Vtk {
    let sub = &solver.problem().subs[i];
    let mesh = &sub.mesh;
    let points: Vec<f64> = mesh.nodes.iter().flatten().copied().collect();
    let mut connectivity = Vec::with_capacity(8 * mesh.elements.len());
    let mut offsets = Vec::with_capacity(mesh.elements.len());
    let mut types = Vec::with_capacity(mesh.elements.len());
    for e in &mesh.elements {
        connectivity.extend(e.nodes().iter().map(|&n| n as u64));
        offsets.push(connectivity.len() as u64);
        types.push(match e {
            Element::Hex8(_) => CellType::Hexahedron,
            Element::Tet4(_) => CellType::Tetra,
        });
    }
    let stress = post::element_stress(solver, i, &f.u);
    let von_mises: Vec<f64> = stress.iter().map(hex8::von_mises).collect();
    let tensors: Vec<f64> = stress
        .iter()
        .flat_map(|&[xx, yy, zz, xy, yz, zx]| [xx, xy, zx, xy, yy, yz, zx, yz, zz])
        .collect();
    let cells = mesh.elements.len();
    let data = Attributes {
        point: vec![
            Attribute::DataArray(DataArray::vectors(POINT_FIELDS[0]).with_data(f.u.clone())),
            Attribute::DataArray(DataArray::vectors(POINT_FIELDS[1]).with_data(f.v.clone())),
            Attribute::DataArray(
                DataArray::vectors(POINT_FIELDS[2]).with_data(
                    f.v.iter()
                        .zip(&prev.v)
                        .map(|(a, b)| 0.5 * (a + b))
                        .collect::<Vec<f64>>(),
                ),
            ),
        ],
        cell: vec![
            Attribute::DataArray(DataArray::scalars(CELL_FIELDS[0], 1).with_data(von_mises)),
            Attribute::DataArray(DataArray::tensors(CELL_FIELDS[1]).with_data(tensors)),
            Attribute::DataArray(
                DataArray::scalars(CELL_FIELDS[2], 1).with_data(vec![i as i32; cells]),
            ),
            Attribute::DataArray(DataArray::scalars(CELL_FIELDS[3], 1).with_data(vec![
                sub.material_id
                    as i32;
                cells
            ])),
        ],
    };
    Vtk {
        version: Version::new((1, 0)),
        title,
        byte_order: ByteOrder::LittleEndian,
        file_path: None,
        data: DataSet::inline(UnstructuredGridPiece {
            points: points.into(),
            cells: Cells {
                cell_verts: VertexNumbers::XML {
                    connectivity,
                    offsets,
                },
                types,
            },
            data,
        }),
    }
}

/// Writes the grid of substructure `i` with fields `f` (and `prev`, the step before's) to
/// `path` (.vtu).
pub fn write(
    solver: &Solver,
    i: usize,
    f: &SubFields,
    prev: &SubFields,
    path: &Path,
) -> anyhow::Result<()> {
    let title = format!(
        "Lopin {} {}",
        solver.problem().name,
        solver.problem().subs[i].name
    );
    grid(solver, i, f, prev, title)
        .export(path)
        .map_err(|e| anyhow::anyhow!("{e:?}"))
        .with_context(|| format!("writing {}", path.display()))
}
