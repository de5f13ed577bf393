//! Admission of a scene before anything large is allocated: the sizes of the problem a scene
//! describes (substructures, elements, nodes, dofs, interface trace entries, steps), computed
//! with checked arithmetic from the scene alone — no mesh is built and a `[granular]` table is
//! not expanded — and the memory a solve will hold (METHOD §11: s = (F, W) per substructure trace
//! and its unrelaxed copy, ŝ = (F̂, Ŵ) per interface side, all over steps 0..N; the skip cache of
//! whole-interval runs; the assembled operators; an estimate of the factorizations of S and of
//! the homogenized operators of METHOD §9), judged against the memory this machine has. A
//! request that cannot fit is refused with the numbers and with what would make it fit. `run`,
//! `sweep`, `estimate` and the explorer all pass through [`admit`] (scene validation calls it
//! with the smallest shape a solve can take).

use std::collections::HashMap;

use crate::error::{LopinError, Result};
use crate::scene::face_index::FaceIndex;
use crate::scene::settings::FactorPrecision;
use crate::scene::spec::face_of;
use crate::scene::spec::{InterfaceKind, SceneSpec};

/// Bytes per double.
const F64: u128 = 8;
/// Bytes per stored factor entry (value and row index).
const FACTOR_ENTRY: u128 = 16;
/// Bytes the `lopin` process holds whatever it solves: its code and libraries, the threads'
/// stacks, the allocator's arenas and the solver's per-step records (the smallest scenes run at
/// about 24 MiB of resident memory).
const PROCESS_BYTES: u64 = 32 << 20;
/// Share of the available memory a solve may plan to use.
const USABLE: f64 = 0.9;
/// Environment variable that caps the memory Lopin plans with (bytes, or with a KiB, MiB, GiB
/// or TiB suffix), e.g. to leave room for other jobs.
pub const MEMORY_LIMIT_VAR: &str = "LOPIN_MEMORY_LIMIT";

/// How a solve will run, as far as memory is concerned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SolveShape {
    /// Time-window length in steps (None: the whole interval).
    pub window: Option<usize>,
    /// Two-scale linear stage (homogenized operators, no skip cache).
    pub two_scale: bool,
    /// Whether whole-interval runs keep the skip cache.
    pub skip_unchanged: bool,
}

impl SolveShape {
    /// The shape a scene asks for in its `[solver]` table (skip cache on).
    pub fn of_scene(spec: &SceneSpec) -> Self {
        Self {
            window: spec.solver.window.and_then(|w| w.steps()),
            two_scale: spec.solver.two_scale.unwrap_or(false),
            skip_unchanged: true,
        }
    }

    /// The smallest a solve of any shape holds (one-step windows: no skip cache).
    pub fn smallest() -> Self {
        Self {
            window: Some(1),
            two_scale: false,
            skip_unchanged: false,
        }
    }
}

/// What a solve of a scene will hold, from the scene alone.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Footprint {
    /// Substructures.
    pub substructures: usize,
    /// Hexahedra.
    pub elements: usize,
    /// Mesh nodes (shared interface nodes counted once per substructure).
    pub nodes: usize,
    /// Degrees of freedom.
    pub dofs: usize,
    /// Interface trace entries over all substructures (Σ interface-side dofs).
    pub trace_entries: usize,
    /// Time steps N.
    pub steps: usize,
    /// Estimated distinct factorizations of S.
    pub factorizations: usize,
    /// Bytes of s, its unrelaxed copy and ŝ over steps 0..N (METHOD §11).
    pub interface_bytes: u64,
    /// Bytes of the skip cache (whole-interval single-scale runs).
    pub cache_bytes: u64,
    /// Bytes of the assembled stiffness matrices, masses and per-substructure work vectors.
    pub operator_bytes: u64,
    /// Estimated bytes of the factorizations of S.
    pub factor_bytes: u64,
    /// Estimated bytes of the homogenized operators (two-scale only).
    pub macro_bytes: u64,
    /// Bytes of the process itself, whatever it solves.
    pub process_bytes: u64,
    /// Solves held at once (a study's chains on one process); every part but the process's own
    /// bytes is held that many times.
    pub copies: usize,
}

impl Footprint {
    /// Total bytes.
    pub fn total_bytes(&self) -> u64 {
        self.solve_bytes()
            .saturating_mul(self.copies.max(1) as u64)
            .saturating_add(self.process_bytes)
    }

    /// Bytes of one solve.
    pub fn solve_bytes(&self) -> u64 {
        self.interface_bytes
            .saturating_add(self.cache_bytes)
            .saturating_add(self.operator_bytes)
            .saturating_add(self.factor_bytes)
            .saturating_add(self.macro_bytes)
    }

    /// Human-readable lines.
    pub fn lines(&self) -> Vec<String> {
        vec![
            format!(
                "{} dofs, {} substructures, {} hexahedra, {} trace entries, {} steps",
                self.dofs, self.substructures, self.elements, self.trace_entries, self.steps
            ),
            format!(
                "memory: {}interface fields {} + skip cache {} + operators {} + factors about \
                 {}{}{} + the process {} = about {}",
                if self.copies > 1 { "(" } else { "" },
                bytes(self.interface_bytes),
                bytes(self.cache_bytes),
                bytes(self.operator_bytes),
                bytes(self.factor_bytes),
                if self.macro_bytes > 0 {
                    format!(" + homogenized operators about {}", bytes(self.macro_bytes))
                } else {
                    String::new()
                },
                if self.copies > 1 {
                    format!(") × {} solves at once", self.copies)
                } else {
                    String::new()
                },
                bytes(self.process_bytes),
                bytes(self.total_bytes())
            ),
        ]
    }
}

/// The memory a solve may plan with, and where that figure comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MemoryBudget {
    /// Bytes.
    pub bytes: u64,
    /// Where the figure comes from.
    pub source: &'static str,
}

/// The memory this machine has for a solve: `LOPIN_MEMORY_LIMIT` if set, else the available
/// memory the kernel reports (`MemAvailable` of /proc/meminfo), on wasm32 the 4 GiB a 32-bit
/// address space holds; None where nothing is known. A malformed `LOPIN_MEMORY_LIMIT` is an
/// error naming it.
pub fn machine_memory() -> Result<Option<MemoryBudget>> {
    #[cfg(target_arch = "wasm32")]
    {
        Ok(Some(MemoryBudget {
            bytes: 4 << 30,
            source: "the 32-bit address space of WebAssembly",
        }))
    }
    #[cfg(not(target_arch = "wasm32"))]
    {
        if let Ok(text) = std::env::var(MEMORY_LIMIT_VAR) {
            let bytes = parse_bytes(&text).ok_or_else(|| {
                LopinError::setting(
                    MEMORY_LIMIT_VAR,
                    format!(
                        "expected a number of bytes, optionally with a KiB, MiB, GiB or TiB \
                         suffix (e.g. 8GiB), got `{text}`"
                    ),
                )
            })?;
            return Ok(Some(MemoryBudget {
                bytes,
                source: MEMORY_LIMIT_VAR,
            }));
        }
        let Ok(info) = std::fs::read_to_string("/proc/meminfo") else {
            return Ok(None);
        };
        Ok(info
            .lines()
            .find_map(|l| l.strip_prefix("MemAvailable:"))
            .and_then(|rest| rest.trim().strip_suffix("kB"))
            .and_then(|kb| kb.trim().parse::<u64>().ok())
            .map(|kb| MemoryBudget {
                bytes: kb.saturating_mul(1024),
                source: "available memory (MemAvailable of /proc/meminfo)",
            }))
    }
}

/// Parses "123", "1.5e9", "512MiB", "8 GiB", "2TiB".
pub fn parse_bytes(text: &str) -> Option<u64> {
    const KI: f64 = 1024.0;
    let units = [
        ("TiB", KI * KI * KI * KI),
        ("GiB", KI * KI * KI),
        ("MiB", KI * KI),
        ("KiB", KI),
        ("T", KI * KI * KI * KI),
        ("G", KI * KI * KI),
        ("M", KI * KI),
        ("K", KI),
        ("B", 1.0),
    ];
    let t = text.trim();
    let (number, scale) = units
        .iter()
        .find_map(|(u, scale)| t.strip_suffix(u).map(|n| (n, *scale)))
        .unwrap_or((t, 1.0));
    let value: f64 = number.trim().parse().ok()?;
    let b = value * scale;
    (b.is_finite() && b >= 1.0 && b < u64::MAX as f64).then_some(b as u64)
}

/// Checks that a solve of `spec` in `shape` fits this machine, before anything large is
/// allocated: the sizes are counted with checked arithmetic (a count that does not fit is an
/// error naming the fields), the memory compared with [`machine_memory`]. Returns the footprint.
pub fn admit(spec: &SceneSpec, source: &str, shape: SolveShape) -> Result<Footprint> {
    admit_with_meshes(spec, source, shape, &[])
}

/// [`admit`] with the meshes of the scene's mesh bodies counted, once they are read.
pub fn admit_with_meshes(
    spec: &SceneSpec,
    source: &str,
    shape: SolveShape,
    meshes: &[MeshSize],
) -> Result<Footprint> {
    let fp = footprint_with_meshes(spec, source, shape, meshes)?;
    fits(spec, source, fp)
}

/// [`admit`] for `copies` solves held at once by one process (a study's chains): refused, with
/// how many would fit, when they do not.
pub fn admit_copies(
    spec: &SceneSpec,
    source: &str,
    shape: SolveShape,
    copies: usize,
) -> Result<Footprint> {
    let fp = Footprint {
        copies: copies.max(1),
        ..footprint(spec, source, shape)?
    };
    fits(spec, source, fp)
}

/// `fp` if it fits this machine's memory, else the refusal with what would fit.
fn fits(spec: &SceneSpec, source: &str, fp: Footprint) -> Result<Footprint> {
    let Some(budget) = machine_memory()? else {
        return Ok(fp);
    };
    let limit = (budget.bytes as f64 * USABLE) as u64;
    if fp.total_bytes() <= limit {
        return Ok(fp);
    }
    Err(LopinError::TooLarge {
        source_name: source.to_string(),
        needed: bytes(fp.total_bytes()),
        available: format!("{} ({})", bytes(budget.bytes), budget.source),
        detail: fp.lines().join("; "),
        remedy: remedies(&fp, limit, spec.granular_poly.is_some()),
    })
}

/// What would make a footprint fit under `limit` bytes (`meshed`: a sample gmsh meshes, whose
/// mesh is coarsened by its `mesh_size`).
fn remedies(fp: &Footprint, limit: u64, meshed: bool) -> String {
    let mut out = Vec::new();
    if fp.copies > 1 {
        let one = fp.solve_bytes().max(1) as u128;
        let most = (limit as u128).saturating_sub(fp.process_bytes as u128) / one;
        if most >= 1 {
            out.push(format!(
                "fewer solves at once: at most {most} (now {}; `--chains`)",
                fp.copies
            ));
        }
    }
    // what one solve may hold: the limit less the process's own bytes, shared by the copies
    let room = (limit as u128).saturating_sub(fp.process_bytes as u128) / fp.copies.max(1) as u128;
    if room == 0 {
        return format!(
            "a memory limit above the {} the process itself holds",
            bytes(fp.process_bytes)
        );
    }
    let fixed = fp.operator_bytes as u128 + fp.factor_bytes as u128 + fp.macro_bytes as u128;
    let n1 = fp.steps as u128 + 1;
    let per_step = (fp.interface_bytes as u128 + fp.cache_bytes as u128) / n1;
    let smallest_per_step = fp.interface_bytes as u128 / n1;
    if fp.cache_bytes > 0 && (fp.solve_bytes() - fp.cache_bytes) as u128 <= room {
        out.push(format!(
            "time windows (`--window W` or `solver.window`) drop the skip cache of {}",
            bytes(fp.cache_bytes)
        ));
    }
    if room > fixed && per_step > 0 {
        let steps = ((room - fixed) / per_step).saturating_sub(1);
        let steps_windowed = ((room - fixed) / smallest_per_step.max(1)).saturating_sub(1);
        if steps >= 1 {
            out.push(format!(
                "fewer steps: `time.steps` at most {} (now {})",
                steps, fp.steps
            ));
        } else if fp.cache_bytes > 0 && steps_windowed >= 1 {
            out.push(format!(
                "fewer steps with time windows: `time.steps` at most {steps_windowed} (now {})",
                fp.steps
            ));
        }
    }
    // interface fields scale with the faces (c⁻²), operators and factors with the volume (c⁻³)
    let surface = fp.interface_bytes as f64 + fp.cache_bytes as f64;
    let volume = fixed as f64;
    let coarser = (2..=1 << 20).find(|&c| {
        let c = c as f64;
        surface / (c * c) + volume / (c * c * c) <= room as f64
    });
    match coarser {
        Some(c) if meshed => out.push(format!(
            "a coarser mesh: `granular_poly.mesh_size` about {c}× larger"
        )),
        Some(c) => out.push(format!(
            "a coarser mesh: about {c}× fewer hexahedra along each axis (smaller `divisions`, \
             `cell_elements` or `--refine`)"
        )),
        None => out.push("a much smaller model".into()),
    }
    out.join("; or ")
}

/// One group of identical substructures: `count` pieces of `div` hexahedra.
struct PieceGroup {
    count: u128,
    div: [u128; 3],
    /// Distinct factorizations the group is expected to need.
    classes: u128,
    /// Whether the group stores a stiffness matrix of its own (false: it shares that of an
    /// earlier group of the same mesh and material).
    own_stiffness: bool,
}

/// The sizes and memory of a solve of `spec` in `shape`, from the scene alone (checked
/// arithmetic; a count that overflows is an error naming the fields).
pub fn footprint(spec: &SceneSpec, source: &str, shape: SolveShape) -> Result<Footprint> {
    footprint_with_meshes(spec, source, shape, &[])
}

/// The size of a mesh body's mesh as read from its file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MeshSize {
    /// Nodes.
    pub nodes: usize,
    /// Substructures the body is cut into.
    pub substructures: usize,
}

/// [`footprint`] with the mesh bodies' meshes counted (without them, a scene's mesh bodies
/// count nothing: their sizes are known once their files are read).
pub fn footprint_with_meshes(
    spec: &SceneSpec,
    source: &str,
    shape: SolveShape,
    meshes: &[MeshSize],
) -> Result<Footprint> {
    let overflow = |field: &str| too_large(source, field);
    let (groups, trace) = scene_pieces(spec, source, meshes)?;
    let fit = |x: u128, field: &str| usize::try_from(x).map_err(|_| overflow(field));
    let field = if spec.granular.is_some() {
        "granular"
    } else if spec.granular_poly.is_some() {
        "granular_poly"
    } else {
        "body"
    };
    let precision = spec.solver.factors.unwrap_or_default();
    let totals = group_totals(&groups, shape, precision, source, field)?;
    let n1 = spec.time.steps as u128 + 1;
    // s, s_new (per substructure trace) and ŝ (per interface side): F and W each
    let interface = n1.saturating_mul(trace).saturating_mul(2 * F64 * 3);
    let whole = shape.window.is_none_or(|w| w >= spec.time.steps);
    let cache = if whole && shape.skip_unchanged && !shape.two_scale {
        n1.saturating_mul(trace).saturating_mul(4 * F64)
    } else {
        0
    };
    // byte counts beyond 16 EiB are shown as 16 EiB: the verdict is the same
    let to_u64 = |x: u128| u64::try_from(x).unwrap_or(u64::MAX);
    Ok(Footprint {
        substructures: fit(totals.substructures, field)?,
        elements: fit(totals.elements, field)?,
        nodes: fit(totals.nodes, field)?,
        dofs: fit(
            totals.nodes.checked_mul(3).ok_or_else(|| overflow(field))?,
            field,
        )?,
        trace_entries: fit(trace, field)?,
        steps: spec.time.steps,
        factorizations: fit(totals.classes, field)?,
        interface_bytes: to_u64(interface),
        cache_bytes: to_u64(cache),
        operator_bytes: to_u64(totals.operator),
        factor_bytes: to_u64(totals.factor),
        macro_bytes: to_u64(totals.macro_),
        process_bytes: PROCESS_BYTES,
        copies: 1,
    })
}

/// The error for a count of `field` in `source` that overflows.
fn too_large(source: &str, field: &str) -> LopinError {
    LopinError::scene(
        source,
        field,
        "the model this asks for is too large to count (its size overflows 64-bit \
         arithmetic)",
    )
}

/// The groups of substructures `spec` describes and their trace entries: those of its
/// `[granular]` table, else of its `[granular_poly]` sample, else of its listed bodies followed
/// by its mesh bodies (`meshes`, or the sizes their files announce when it is empty). An error
/// naming the table when a count overflows.
fn scene_pieces(
    spec: &SceneSpec,
    source: &str,
    meshes: &[MeshSize],
) -> Result<(Vec<PieceGroup>, u128)> {
    let overflow = |field: &str| too_large(source, field);
    Ok(match (&spec.granular, &spec.granular_poly) {
        (Some(g), _) => granular_pieces(g).ok_or_else(|| overflow("granular"))?,
        (None, Some(g)) => polyhedral_pieces(g).ok_or_else(|| overflow("granular_poly"))?,
        (None, None) => {
            let (mut groups, trace) = body_pieces(spec).ok_or_else(|| overflow("body"))?;
            let announced;
            let meshes = if meshes.is_empty() {
                announced = announced_meshes(spec, source);
                &announced
            } else {
                meshes
            };
            let (more, more_trace) = mesh_pieces(meshes).ok_or_else(|| overflow("mesh_body"))?;
            groups.extend(more);
            (groups, trace.saturating_add(more_trace))
        }
    })
}

/// The sizes of all groups of substructures together.
struct GroupTotals {
    substructures: u128,
    elements: u128,
    nodes: u128,
    operator: u128,
    factor: u128,
    macro_: u128,
    classes: u128,
}

/// The sizes of `groups` summed in order: counts checked (an overflow is an error naming
/// `field`), byte counts saturating, homogenized operators counted only for a two-scale
/// `shape`, factors in the `precision` each group's size gets.
fn group_totals(
    groups: &[PieceGroup],
    shape: SolveShape,
    precision: FactorPrecision,
    source: &str,
    field: &str,
) -> Result<GroupTotals> {
    let overflow = |field: &str| too_large(source, field);
    let mut t = GroupTotals {
        substructures: 0,
        elements: 0,
        nodes: 0,
        operator: 0,
        factor: 0,
        macro_: 0,
        classes: 0,
    };
    for g in groups {
        let sizes = group_sizes(g, precision).ok_or_else(|| overflow(field))?;
        t.substructures = t
            .substructures
            .checked_add(g.count)
            .ok_or_else(|| overflow(field))?;
        t.elements = t
            .elements
            .checked_add(sizes.elements)
            .ok_or_else(|| overflow(field))?;
        t.nodes = t
            .nodes
            .checked_add(sizes.nodes)
            .ok_or_else(|| overflow(field))?;
        // byte counts saturate: beyond 2¹²⁸ the verdict is the same
        t.operator = t.operator.saturating_add(sizes.operator_bytes);
        t.factor = t.factor.saturating_add(sizes.factor_bytes);
        t.classes = t.classes.saturating_add(g.classes);
        if shape.two_scale {
            t.macro_ = t.macro_.saturating_add(sizes.macro_bytes);
        }
    }
    Ok(t)
}

/// What one group of identical substructures holds; None when a count overflows.
struct GroupSizes {
    elements: u128,
    nodes: u128,
    operator_bytes: u128,
    factor_bytes: u128,
    macro_bytes: u128,
}

fn group_sizes(g: &PieceGroup, precision: FactorPrecision) -> Option<GroupSizes> {
    let product = |v: [u128; 3]| v[0].checked_mul(v[1])?.checked_mul(v[2]);
    let node_dims = g.div.map(|d| d.saturating_add(1));
    let per_piece_nodes = product(node_dims)?;
    let ndof = per_piece_nodes.checked_mul(3)?;
    // stiffness: its lower triangle (of 9 entries per pair of neighbouring nodes) in CSC with
    // 32-bit row indices, once per group; mass, linear-stage work and window-start vectors (13
    // per dof) per substructure
    let nnz = product(g.div.map(|d| d.saturating_mul(3).saturating_add(1)))?.checked_mul(9)?;
    let lower = nnz.saturating_add(ndof) / 2;
    let operator_bytes = lower
        .saturating_mul(if g.own_stiffness { F64 + 4 } else { 0 })
        .saturating_add(g.count.saturating_mul(ndof).saturating_mul(13 * F64));
    // the factor of S per expected distinct factorization: a band of the two smallest node
    // layers, or the n^(4/3) growth of nested dissection on large 3D meshes (35 n^(4/3): 19.8 M
    // entries measured for 20,577 dofs), whichever is smaller
    let mut dims = node_dims;
    dims.sort_unstable();
    let band = ndof.saturating_mul(dims[0].saturating_mul(dims[1]).saturating_mul(3).min(ndof));
    let dissection = (35.0 * (ndof as f64).powf(4.0 / 3.0)).min(u128::MAX as f64 / 2.0) as u128;
    // a factor kept in single precision stores half the bytes per entry
    let entry = if precision.single_for(usize::try_from(ndof).unwrap_or(usize::MAX)) {
        FACTOR_ENTRY / 2
    } else {
        FACTOR_ENTRY
    };
    let factor_bytes = g
        .classes
        .saturating_mul(band.min(dissection))
        .saturating_mul(entry);
    // Z_E: 9 macro fields per face of the substructure, a column per field
    let macro_bytes = g.classes.saturating_mul(ndof).saturating_mul(54 * F64);
    Some(GroupSizes {
        elements: g.count.checked_mul(product(g.div)?)?,
        nodes: g.count.checked_mul(per_piece_nodes)?,
        operator_bytes,
        factor_bytes,
        macro_bytes,
    })
}

/// The substructures of a `[granular]` table without expanding it: every cell one substructure
/// of m³ hexahedra; trace entries of every internal face (both sides) and of the top (one
/// velocity component) and bottom (clamped) faces. None on overflow.
fn granular_pieces(g: &crate::scene::tables::GranularSpec) -> Option<(Vec<PieceGroup>, u128)> {
    let n = g.grid.map(|x| x as u128);
    let m = g.cell_elements as u128;
    let cells = n[0].checked_mul(n[1])?.checked_mul(n[2])?;
    let face_nodes = (m + 1).checked_mul(m + 1)?;
    let mut trace = 0u128;
    for a in 0..3 {
        let planes = n[a].saturating_sub(1);
        let per_plane = n[(a + 1) % 3].checked_mul(n[(a + 2) % 3])?;
        // two sides, three components
        trace = trace.checked_add(
            planes
                .checked_mul(per_plane)?
                .checked_mul(6)?
                .checked_mul(face_nodes)?,
        )?;
    }
    let top_bottom = n[0]
        .checked_mul(n[1])?
        .checked_mul(face_nodes)?
        .checked_mul(4)?;
    trace = trace.checked_add(top_bottom)?;
    let grain_cells = (g.grains as u128)
        .checked_mul(g.grain_cells[1] as u128)?
        .min(cells);
    let div = [m; 3];
    let groups = vec![
        PieceGroup {
            count: cells - grain_cells,
            div,
            classes: (cells - grain_cells).min(27),
            own_stiffness: true,
        },
        PieceGroup {
            count: grain_cells,
            div,
            classes: grain_cells.min(27),
            own_stiffness: true,
        },
    ];
    Some((groups, trace))
}

/// Nodes per cubic metre of a gmsh tetrahedral mesh of size h, times h³, measured on the
/// polyhedral samples: `granular-poly` 5,714 nodes for a 0.1 m cube at h = 6 mm (1.23),
/// `granular-poly-paper` 237,172 for a 0.5 m cube at h = 7.6 mm (0.83); the estimate of
/// [`polyhedral_pieces`] takes the larger.
const TET_NODES_PER_H3: f64 = 1.23;

/// The substructures of a `[granular_poly]` sample, before it is meshed: the matrix parts and
/// one per grain, all counted as cubes of hexahedra holding the nodes a tetrahedral mesh of the
/// cube at `mesh_size` has ([`TET_NODES_PER_H3`]) shared out equally, every face an interface
/// side. None on overflow (or a size that is not finite).
fn polyhedral_pieces(
    g: &crate::scene::tables::GranularPolySpec,
) -> Option<(Vec<PieceGroup>, u128)> {
    let pieces = (g.matrix_substructures as u128).checked_add(g.grains as u128)?;
    let nodes = TET_NODES_PER_H3 * (g.side / g.mesh_size).powi(3);
    if !nodes.is_finite() || nodes >= 1e30 || pieces == 0 {
        return None;
    }
    let (group, trace) = cube_pieces(nodes, pieces)?;
    Some((vec![group], trace))
}

/// `pieces` substructures sharing `nodes` equally, each counted as a cube of hexahedra holding
/// its share, every face an interface side (two sides of three components on each of six
/// faces, halved: every face is shared), each its own factorization. None on overflow.
fn cube_pieces(nodes: f64, pieces: u128) -> Option<(PieceGroup, u128)> {
    let per_piece = (nodes / pieces as f64).max(8.0);
    let m = (per_piece.cbrt() - 1.0).round().max(1.0) as u128;
    let trace = pieces
        .checked_mul(9)?
        .checked_mul((m + 1).checked_mul(m + 1)?)?;
    let group = PieceGroup {
        count: pieces,
        div: [m; 3],
        classes: pieces,
        own_stiffness: true,
    };
    Some((group, trace))
}

/// The mesh bodies' sizes before their files are read: each counted with every node its MSH
/// file announces (a file several bodies share counts whole for each, an upper bound); a
/// `.geo` script not meshed yet, or a file that cannot be read, counts nothing here (the build
/// admits the meshes it reads).
fn announced_meshes(spec: &SceneSpec, source: &str) -> Vec<MeshSize> {
    #[cfg(feature = "msh")]
    {
        spec.mesh_bodies
            .iter()
            .filter_map(|b| {
                let path = crate::scene::mesh_bodies::mesh_path(source, &b.mesh);
                let nodes = crate::mesh::msh::announced_nodes(&path)?;
                Some(MeshSize {
                    nodes: usize::try_from(nodes).unwrap_or(usize::MAX),
                    substructures: b.substructures.unwrap_or(1),
                })
            })
            .collect()
    }
    #[cfg(not(feature = "msh"))]
    {
        let _ = (spec, source);
        Vec::new()
    }
}

/// The substructures of mesh bodies as read, each body's nodes shared out among its
/// substructures ([`cube_pieces`]: the operators and factors of a tetrahedral mesh are no larger
/// than those of a hexahedral one with as many nodes). None on overflow.
fn mesh_pieces(meshes: &[MeshSize]) -> Option<(Vec<PieceGroup>, u128)> {
    let mut groups = Vec::with_capacity(meshes.len());
    let mut trace = 0u128;
    for m in meshes {
        let (group, more) = cube_pieces(m.nodes as f64, m.substructures.max(1) as u128)?;
        trace = trace.checked_add(more)?;
        groups.push(group);
    }
    Some((groups, trace))
}

/// A box face: its axis and whether it is the upper one.
type FaceKey = (usize, bool);

/// The substructures of listed bodies: each body cut into split[0]·split[1]·split[2] equal
/// boxes; trace entries of the cuts (both sides), of the boundary conditions (one per prescribed
/// component) and of the faces another body touches (or faces across a contact search distance).
/// None on overflow.
fn body_pieces(spec: &SceneSpec) -> Option<(Vec<PieceGroup>, u128)> {
    let mut groups = Vec::with_capacity(spec.bodies.len());
    let mut trace = 0u128;
    let rules = interface_rules(spec);
    let faces = FaceIndex::new(&spec.bodies);
    let mut shared = HashMap::new();
    let search = rules.values().fold(0.0f64, |m, r| m.max(r.1));
    let prescribed = prescribed_components(spec);
    let sides = BodySides {
        spec,
        rules: &rules,
        faces: &faces,
        search,
        prescribed: &prescribed,
    };
    for (i, b) in spec.bodies.iter().enumerate() {
        let split = b.split.map(|x| x.max(1) as u128);
        let div: [u128; 3] = std::array::from_fn(|a| b.divisions[a] as u128 / split[a]);
        let count = split[0].checked_mul(split[1])?.checked_mul(split[2])?;
        trace = sides.add_body_trace(trace, i, split, div)?;
        // bodies of one mesh (divisions and extents) and material share their stiffness and,
        // up to the 27 positions a piece can take among its neighbours, their factorizations
        let key = (
            b.divisions,
            b.split,
            // extents to a relative 1e-6: cells of a grid differ in their last bits
            std::array::from_fn::<i64, 3, _>(|a| {
                ((b.max[a] - b.min[a]).log2() * 1e6).round() as i64
            }),
            b.material.as_str(),
        );
        let used = shared.entry(key).or_insert(0u128);
        let classes = count.min(27).min(27 - *used);
        let own_stiffness = *used == 0;
        *used += classes;
        groups.push(PieceGroup {
            count,
            div,
            classes,
            own_stiffness,
        });
    }
    Some((groups, trace))
}

/// The kind and contact search distance (0 when none) of each declared interface between two
/// listed bodies, keyed by the bodies' indices (smaller first); a later declaration of the same
/// pair replaces an earlier one.
fn interface_rules(spec: &SceneSpec) -> HashMap<(usize, usize), (InterfaceKind, f64)> {
    let index: HashMap<&str, usize> = spec
        .bodies
        .iter()
        .enumerate()
        .map(|(i, b)| (b.name.as_str(), i))
        .collect();
    let mut rules: HashMap<(usize, usize), (InterfaceKind, f64)> = HashMap::new();
    for it in &spec.interfaces {
        if let (Some(&a), Some(&b)) = (
            index.get(it.bodies[0].as_str()),
            index.get(it.bodies[1].as_str()),
        ) {
            rules.insert((a.min(b), a.max(b)), (it.kind, it.search.unwrap_or(0.0)));
        }
    }
    rules
}

/// The key of a face name in [`prescribed_components`]: its axis and whether it is the upper
/// face (None for a name that is not a box face).
fn face_key(f: &str) -> Option<FaceKey> {
    face_of(f).map(|(a, s)| (a, s > 0.0))
}

/// The displacement components the boundary conditions prescribe on each body face (3 for a
/// clamped face), summed over the conditions naming the same body and face.
fn prescribed_components(spec: &SceneSpec) -> HashMap<(&str, Option<FaceKey>), u128> {
    let mut prescribed: HashMap<(&str, Option<FaceKey>), u128> = HashMap::new();
    for bc in &spec.boundaries {
        let components = if bc.clamped {
            3
        } else {
            bc.components().iter().filter(|(_, c)| c.is_some()).count() as u128
        };
        *prescribed
            .entry((bc.body.as_str(), face_key(&bc.face)))
            .or_default() += components;
    }
    prescribed
}

/// The name of the box face on axis `a` (the upper one when `upper`).
fn face_name(a: usize, upper: bool) -> &'static str {
    match (a, upper) {
        (0, false) => "x-",
        (0, true) => "x+",
        (1, false) => "y-",
        (1, true) => "y+",
        (2, false) => "z-",
        _ => "z+",
    }
}

/// What the trace entries of the listed bodies' faces depend on: the interface rules between
/// bodies, the face index, the largest contact search distance and the prescribed components
/// per body face.
struct BodySides<'a> {
    spec: &'a SceneSpec,
    rules: &'a HashMap<(usize, usize), (InterfaceKind, f64)>,
    faces: &'a FaceIndex,
    search: f64,
    prescribed: &'a HashMap<(&'a str, Option<FaceKey>), u128>,
}

impl BodySides<'_> {
    /// `trace` plus the trace entries of body `i` cut into `split` boxes of `div` hexahedra:
    /// per axis, those of its inner cuts (two sides of three components), then those of its
    /// lower and upper faces (one per prescribed component, three per touched share). None on
    /// overflow.
    fn add_body_trace(
        &self,
        mut trace: u128,
        i: usize,
        split: [u128; 3],
        div: [u128; 3],
    ) -> Option<u128> {
        let b = &self.spec.bodies[i];
        let face_nodes = |a: usize| (div[(a + 1) % 3] + 1).checked_mul(div[(a + 2) % 3] + 1);
        for a in 0..3 {
            let cross = split[(a + 1) % 3].checked_mul(split[(a + 2) % 3])?;
            let fnodes = face_nodes(a)?;
            // cuts inside the body: two sides of three components
            trace = trace.checked_add(
                split[a]
                    .saturating_sub(1)
                    .checked_mul(cross)?
                    .checked_mul(6)?
                    .checked_mul(fnodes)?,
            )?;
            // the body's own faces on this axis
            let body_face_nodes = cross.checked_mul(fnodes)?;
            for sign in [-1.0, 1.0] {
                let name = face_name(a, sign > 0.0);
                let components = self
                    .prescribed
                    .get(&(b.name.as_str(), face_key(name)))
                    .copied()
                    .unwrap_or(0);
                let touched =
                    touched_fraction(self.spec, self.rules, self.faces, self.search, i, a, sign);
                let sides = components as f64 + 3.0 * touched;
                trace = trace.checked_add((body_face_nodes as f64 * sides).ceil() as u128)?;
            }
        }
        Some(trace)
    }
}

/// The fraction of body `i`'s face (axis `a`, outward `sign`) that other bodies touch (or face
/// across a contact search distance, at most `search`), at most 1; the other bodies are taken
/// from the face index, in increasing order.
fn touched_fraction(
    spec: &SceneSpec,
    rules: &HashMap<(usize, usize), (InterfaceKind, f64)>,
    faces: &FaceIndex,
    search: f64,
    i: usize,
    a: usize,
    sign: f64,
) -> f64 {
    let b = &spec.bodies[i];
    let plane = if sign > 0.0 { b.max[a] } else { b.min[a] };
    let (u, v) = ((a + 1) % 3, (a + 2) % 3);
    let area = (b.max[u] - b.min[u]) * (b.max[v] - b.min[v]);
    let size = (0..3).map(|c| b.max[c] - b.min[c]).fold(0.0, f64::max);
    let tol = 1e-6 * size;
    let (below, above) = if sign > 0.0 {
        (tol, search.max(0.0) + tol)
    } else {
        (search.max(0.0) + tol, tol)
    };
    let mut touched = 0.0;
    for j in faces.near(b, a, sign, below, above) {
        if j == i {
            continue;
        }
        let o = &spec.bodies[j];
        let (kind, search) = rules
            .get(&(i.min(j), i.max(j)))
            .copied()
            .unwrap_or((InterfaceKind::Perfect, 0.0));
        if kind == InterfaceKind::Free {
            continue;
        }
        let other = if sign > 0.0 { o.min[a] } else { o.max[a] };
        let distance = sign * (other - plane);
        if distance < -tol || distance > search.max(0.0) + tol {
            continue;
        }
        let overlap = |c: usize| (b.max[c].min(o.max[c]) - b.min[c].max(o.min[c])).max(0.0);
        touched += overlap(u) * overlap(v) / area;
    }
    touched.min(1.0)
}

/// Bytes in B, KiB, MiB, GiB, TiB, PiB or EiB.
pub fn bytes(b: u64) -> String {
    const UNITS: [&str; 6] = ["KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
    if b < 1024 {
        return format!("{b} B");
    }
    let mut value = b as f64 / 1024.0;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    let digits = if unit >= 2 { 2 } else { 1 };
    format!("{value:.digits$} {}", UNITS[unit])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::registry;

    fn scene(name: &str) -> SceneSpec {
        registry::parse(name)
            .expect("a registry scene")
            .expect("parses")
    }

    #[test]
    fn counts_that_overflow_are_errors_and_byte_counts_saturate() {
        // 2·10¹⁴ hexahedra per axis: 8·10⁴² elements do not fit any count
        let mut spec = scene("two-blocks");
        spec.bodies[0].divisions = [200_000_000_000_000; 3];
        let e = footprint(&spec, "f.toml", SolveShape::smallest()).expect_err("overflow");
        assert!(e.to_string().contains("too large to count"), "{e}");
        // a granular cell of 10⁷ hexahedra per edge: 10²¹ per cell, counted, bytes saturated
        let mut spec = scene("granular-small");
        if let Some(g) = &mut spec.granular {
            g.cell_elements = 10_000_000;
        }
        let e = footprint(&spec, "g.toml", SolveShape::smallest()).expect_err("overflow");
        assert!(e.to_string().contains("granular"), "{e}");
        if let Some(g) = &mut spec.granular {
            g.cell_elements = 100_000;
        }
        let fp = footprint(&spec, "g.toml", SolveShape::smallest()).expect("counts");
        assert_eq!(fp.elements, 64 * 100_000usize.pow(3));
        assert_eq!(fp.factor_bytes, u64::MAX);
    }

    #[test]
    fn memory_limits_parse_with_their_units() {
        assert_eq!(parse_bytes("123"), Some(123));
        assert_eq!(parse_bytes("1.5e9"), Some(1_500_000_000));
        assert_eq!(parse_bytes("512MiB"), Some(512 << 20));
        assert_eq!(parse_bytes("8 GiB"), Some(8 << 30));
        assert_eq!(parse_bytes("2TiB"), Some(2 << 40));
        for bad in ["", "lots", "-1", "0", "1e300", "5 parsecs"] {
            assert_eq!(parse_bytes(bad), None, "{bad}");
        }
        assert_eq!(bytes(0), "0 B");
        assert_eq!(bytes(1536), "1.5 KiB");
        assert_eq!(bytes(3 << 30), "3.00 GiB");
        assert_eq!(bytes(u64::MAX), "16.00 EiB");
    }
}
