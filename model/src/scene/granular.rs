//! The `granular` scene generator (SCENES.md, section `granular`): a cube of side L cut into a
//! grid of cells, each cell one substructure meshed with m × m × m hexahedra; a seeded random
//! subset of cells grouped into grains (clusters of face-adjacent cells) of a stiffer material,
//! embedded in the matrix. This module owns the `[granular]` table of a scene ([`GranularSpec`]),
//! its validation, the grain placement ([`layout`]) and the expansion into ordinary bodies,
//! interface overrides and boundary conditions ([`expand`]), which `scene::build` calls first.
//!
//! Expansion: one body per cell, named `M[i,j,k]` (matrix) or `G<n>[i,j,k]` (cell of grain n,
//! counted from 1); cells of one grain are joined perfectly (the default), every grain/matrix
//! face is unilateral contact with Coulomb friction f and zero initial gap (one interface
//! override per grain-cell/matrix-cell pair); the z+ faces of the top layer get the velocity
//! −V₀ along z with a (1 − cos) ramp over `ramp_steps` steps, the z− faces of the bottom layer
//! are clamped, the lateral faces are free.

use crate::error::{LopinError, Result};
use crate::scene::cell_set::CellSet;
use crate::scene::spec::{
    BodySpec, BoundarySpec, ComponentSpec, InterfaceKind, InterfaceSpec, SceneSpec,
};
pub use crate::scene::tables::GranularSpec;
use crate::scene::tables::{
    default_friction, default_grain_cells, default_ramp_steps, default_seed, default_split,
    default_velocity,
};
use crate::splitmix::SplitMix64;

impl GranularSpec {
    /// The parameters of SCENES.md with the defaults of the optional fields (seed 1, grains of
    /// 1 to 3 cells, f = 0.3, V₀ = 10 m/s, ramp over 10 steps).
    pub fn new(
        side: f64,
        grid: [usize; 3],
        cell_elements: usize,
        grains: usize,
        matrix: &str,
        grain: &str,
    ) -> Self {
        Self {
            side,
            grid,
            cell_elements,
            grains,
            grain_cells: default_grain_cells(),
            seed: default_seed(),
            matrix: matrix.into(),
            grain: grain.into(),
            friction: default_friction(),
            velocity: default_velocity(),
            ramp_steps: default_ramp_steps(),
            requested_split: default_split(),
        }
    }

    /// Number of cells nx · ny · nz.
    pub fn cell_count(&self) -> usize {
        self.grid.iter().product()
    }
}

/// Attempts at placing one grain before the placement gives up.
const ATTEMPTS_PER_GRAIN: usize = 200;

/// The grain layout of a grid: which cells belong to which grain.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Layout {
    /// Cells along x, y, z.
    pub grid: [usize; 3],
    /// Per cell (index i + nx (j + ny k)): the grain it belongs to (0-based), or None (matrix).
    pub grain_of: Vec<Option<usize>>,
    /// Per grain: its cells, in the order they were added.
    pub grains: Vec<Vec<usize>>,
}

impl Layout {
    /// Index of cell (i, j, k).
    pub fn index(&self, [i, j, k]: [usize; 3]) -> usize {
        i + self.grid[0] * (j + self.grid[1] * k)
    }

    /// (i, j, k) of a cell index.
    pub fn cell(&self, c: usize) -> [usize; 3] {
        let [nx, ny, _] = self.grid;
        [c % nx, (c / nx) % ny, c / (nx * ny)]
    }

    /// The face-adjacent cells of cell `c` inside the grid, in the order x−, x+, y−, y+, z−, z+.
    pub fn neighbours(&self, c: usize) -> Vec<usize> {
        let ijk = self.cell(c);
        let mut out = Vec::with_capacity(6);
        for a in 0..3 {
            if ijk[a] > 0 {
                let mut n = ijk;
                n[a] -= 1;
                out.push(self.index(n));
            }
            if ijk[a] + 1 < self.grid[a] {
                let mut n = ijk;
                n[a] += 1;
                out.push(self.index(n));
            }
        }
        out
    }

    /// The body name of cell `c`: `M[i,j,k]` or `G<n>[i,j,k]` (grains counted from 1).
    pub fn name(&self, c: usize) -> String {
        let [i, j, k] = self.cell(c);
        match self.grain_of[c] {
            Some(g) => format!("G{}[{i},{j},{k}]", g + 1),
            None => format!("M[{i},{j},{k}]"),
        }
    }
}

/// Checks the `[granular]` table of `spec` (errors name `source`, the field and the reason).
pub fn validate(spec: &SceneSpec, source: &str) -> Result<()> {
    let Some(g) = &spec.granular else {
        return Ok(());
    };
    check_no_listed_entries(spec, source)?;
    check_grid(g, source)?;
    check_grains(g, source)?;
    check_materials_and_load(spec, g, source)
}

/// Checks that a scene with a `[granular]` table lists no bodies, interfaces or boundaries of
/// its own (the table generates them).
fn check_no_listed_entries(spec: &SceneSpec, source: &str) -> Result<()> {
    let err = |field: &str, reason: String| Err(LopinError::scene(source, field, reason));
    for (field, len) in [
        ("body", spec.bodies.len()),
        ("interface", spec.interfaces.len()),
        ("boundary", spec.boundaries.len()),
    ] {
        if len > 0 {
            return err(
                field,
                format!(
                    "a scene with a [granular] table generates its bodies, interfaces and \
                     boundaries: remove the {len} [[{field}]] entr{}",
                    if len == 1 { "y" } else { "ies" }
                ),
            );
        }
    }
    Ok(())
}

/// Checks the cube and its grid: a positive finite side, at least one cell along each axis, a
/// cell count that fits a `usize`, and at least one hexahedron per cell edge.
fn check_grid(g: &GranularSpec, source: &str) -> Result<()> {
    let err = |field: &str, reason: String| Err(LopinError::scene(source, field, reason));
    if !(g.side.is_finite() && g.side > 0.0) {
        return err(
            "granular.side",
            format!("must be a positive length, got {}", g.side),
        );
    }
    for (a, &n) in g.grid.iter().enumerate() {
        if n == 0 {
            return err(
                "granular.grid",
                format!("{}: must be at least 1 cell, got 0", ["x", "y", "z"][a]),
            );
        }
    }
    if g.grid
        .iter()
        .try_fold(1usize, |p, &n| p.checked_mul(n))
        .is_none()
    {
        return err("granular.grid", "too many cells".into());
    }
    if g.cell_elements == 0 {
        return err(
            "granular.cell_elements",
            "must be at least 1 hexahedron per cell edge".into(),
        );
    }
    Ok(())
}

/// Checks the grains: a cell range from at least 1 cell, its minimum not above its maximum, its
/// maximum within the grid, the grains at their minimum size fitting in the grid, and a seed
/// TOML can hold (a signed 64-bit integer).
fn check_grains(g: &GranularSpec, source: &str) -> Result<()> {
    let err = |field: &str, reason: String| Err(LopinError::scene(source, field, reason));
    let [lo, hi] = g.grain_cells;
    if lo == 0 {
        return err(
            "granular.grain_cells",
            "a grain has at least 1 cell, got a minimum of 0".into(),
        );
    }
    if lo > hi {
        return err(
            "granular.grain_cells",
            format!("minimum {lo} exceeds maximum {hi}"),
        );
    }
    let cells = g.cell_count();
    if hi > cells {
        return err(
            "granular.grain_cells",
            format!(
                "a grain of up to {hi} cells cannot fit in the grid's {cells} cells: at most \
                 {cells}"
            ),
        );
    }
    if g.grains.checked_mul(lo).is_none_or(|n| n > cells) {
        return err(
            "granular.grains",
            format!(
                "{} grains of at least {lo} cells do not fit in {cells} cells",
                g.grains
            ),
        );
    }
    if i64::try_from(g.seed).is_err() {
        return err(
            "granular.seed",
            format!(
                "must be at most {} (TOML integers are signed), got {}",
                i64::MAX,
                g.seed
            ),
        );
    }
    Ok(())
}

/// Checks the materials and the load: the matrix and grain materials exist in `spec`, the
/// friction coefficient is valid, the velocity is finite, the ramp fits the run, and no
/// `--split` other than 1 was requested.
fn check_materials_and_load(spec: &SceneSpec, g: &GranularSpec, source: &str) -> Result<()> {
    let err = |field: &str, reason: String| Err(LopinError::scene(source, field, reason));
    for (field, name) in [("granular.matrix", &g.matrix), ("granular.grain", &g.grain)] {
        if !spec.materials.iter().any(|m| &m.name == name) {
            return err(field, format!("no material named `{name}`"));
        }
    }
    if let Err(reason) = crate::scene::validate::check_friction(g.friction) {
        return err("granular.friction", reason);
    }
    if !g.velocity.is_finite() {
        return err(
            "granular.velocity",
            format!("must be finite, got {}", g.velocity),
        );
    }
    if let Err(reason) = check_ramp_steps(g.ramp_steps, spec.time.steps) {
        return err("granular.ramp_steps", reason);
    }
    if g.requested_split != 1 {
        return err(
            "granular.grid",
            format!(
                "`--split {}` does not apply to a granular scene: every cell is one \
                 substructure (change granular.grid, or --refine the cells' meshes)",
                g.requested_split
            ),
        );
    }
    Ok(())
}

/// Checks a generator's ramp length against the run: at least one step, and no longer than the
/// run (a ramp the run never finishes leaves the load at a fraction of V₀, or never starts it).
pub(crate) fn check_ramp_steps(ramp_steps: usize, steps: usize) -> std::result::Result<(), String> {
    if ramp_steps == 0 {
        return Err("must be at least 1 step".into());
    }
    if ramp_steps > steps {
        return Err(format!(
            "a ramp of {ramp_steps} steps is longer than the run's {steps} steps (time.steps): \
             the load would never reach its velocity; at most {steps}"
        ));
    }
    Ok(())
}

/// A grain growing inside the free cells: the cells it may take next (its free face neighbours)
/// and those it holds, with every cell ever put on the frontier (to clear it afterwards).
struct Growth<'a> {
    free: &'a CellSet,
    frontier: &'a mut CellSet,
    in_grain: &'a mut [bool],
    touched: &'a mut Vec<usize>,
}

impl Growth<'_> {
    /// Cell `c` joins the grain; its free neighbours outside it join the frontier.
    fn take(&mut self, layout: &Layout, c: usize) {
        self.in_grain[c] = true;
        self.frontier.remove(c);
        for d in layout.neighbours(c) {
            if self.free.contains(d) && !self.in_grain[d] && !self.frontier.contains(d) {
                self.frontier.insert(d);
                self.touched.push(d);
            }
        }
    }
}

/// Places the grains of a validated table: one by one, a random free cell grown to a random size
/// in `grain_cells` by adding random face-adjacent free cells, where a cell is free when neither
/// it nor a face neighbour belongs to an earlier grain (grains never touch: each is embedded in
/// matrix). A grain that cannot grow is drawn again, at most [`ATTEMPTS_PER_GRAIN`] times; then
/// the error names `granular.grains`.
pub fn layout(g: &GranularSpec, source: &str) -> Result<Layout> {
    let cells = g.cell_count();
    let mut layout = Layout {
        grid: g.grid,
        grain_of: vec![None; cells],
        grains: Vec::with_capacity(g.grains.min(cells)),
    };
    // free: neither a grain cell nor a face neighbour of one
    let mut free = CellSet::full(cells);
    // the cells a growing grain may take next, and those it holds
    let mut frontier = CellSet::empty(cells);
    let mut in_grain = vec![false; cells];
    let mut rng = SplitMix64(g.seed);
    let [lo, hi] = g.grain_cells;
    for n in 0..g.grains {
        let mut placed = None;
        for _ in 0..ATTEMPTS_PER_GRAIN {
            if free.is_empty() {
                break;
            }
            let size = lo + rng.below(hi - lo + 1);
            let first = free.nth(rng.below(free.len()));
            let mut grain = vec![first];
            let mut touched = Vec::new();
            let mut grow = Growth {
                free: &free,
                frontier: &mut frontier,
                in_grain: &mut in_grain,
                touched: &mut touched,
            };
            grow.take(&layout, first);
            while grain.len() < size && !grow.frontier.is_empty() {
                let c = grow.frontier.nth(rng.below(grow.frontier.len()));
                grain.push(c);
                grow.take(&layout, c);
            }
            for &c in &touched {
                frontier.remove(c);
            }
            for &c in &grain {
                in_grain[c] = false;
            }
            if grain.len() == size {
                placed = Some(grain);
                break;
            }
        }
        let Some(grain) = placed else {
            return Err(LopinError::scene(
                source,
                "granular.grains",
                format!(
                    "placed {n} of {} grains of {lo} to {hi} cells in the {}×{}×{} grid, then \
                     found no room for grain {} in {ATTEMPTS_PER_GRAIN} attempts (grains may \
                     not touch each other): ask for fewer or smaller grains, a finer grid or \
                     another seed",
                    g.grains,
                    g.grid[0],
                    g.grid[1],
                    g.grid[2],
                    n + 1
                ),
            ));
        };
        for &c in &grain {
            layout.grain_of[c] = Some(n);
            free.remove(c);
            for d in layout.neighbours(c) {
                free.remove(d);
            }
        }
        layout.grains.push(grain);
    }
    Ok(layout)
}

/// The scene with its `[granular]` table expanded into bodies, interface overrides and
/// boundaries (a clone when it has none). Validates the table first.
pub fn expand(spec: &SceneSpec, source: &str) -> Result<SceneSpec> {
    let Some(g) = &spec.granular else {
        return Ok(spec.clone());
    };
    validate(spec, source)?;
    let layout = layout(g, source)?;
    let cells = g.cell_count();
    let names: Vec<String> = (0..cells).map(|c| layout.name(c)).collect();
    let m = g.cell_elements;
    let coordinate = |a: usize, i: usize| g.side * i as f64 / g.grid[a] as f64;
    let bodies = (0..cells)
        .map(|c| {
            let ijk = layout.cell(c);
            BodySpec {
                name: names[c].clone(),
                material: if layout.grain_of[c].is_some() {
                    g.grain.clone()
                } else {
                    g.matrix.clone()
                },
                min: std::array::from_fn(|a| coordinate(a, ijk[a])),
                max: std::array::from_fn(|a| coordinate(a, ijk[a] + 1)),
                divisions: [m; 3],
                split: [1, 1, 1],
                velocity: [0.0; 3],
                elements: None,
                substructures: None,
            }
        })
        .collect();
    let mut interfaces = Vec::new();
    for c in 0..cells {
        if layout.grain_of[c].is_none() {
            continue;
        }
        for d in layout.neighbours(c) {
            if layout.grain_of[d].is_none() {
                interfaces.push(InterfaceSpec {
                    bodies: [names[c].clone(), names[d].clone()],
                    kind: InterfaceKind::Contact,
                    friction: Some(g.friction),
                    gap: Some(0.0),
                    search: None,
                });
            }
        }
    }
    let [nx, ny, nz] = g.grid;
    let layer = |k: usize| (0..nx * ny).map(move |c| c + nx * ny * k);
    let ramp_time = g.ramp_steps as f64 * spec.time.dt;
    let top = layer(nz - 1).map(|c| BoundarySpec {
        body: names[c].clone(),
        face: "z+".into(),
        surface: None,
        clamped: false,
        preload: false,
        x: None,
        y: None,
        z: Some(ComponentSpec::velocity(-g.velocity, ramp_time)),
        normal: None,
    });
    let bottom = layer(0).map(|c| BoundarySpec {
        body: names[c].clone(),
        face: "z-".into(),
        surface: None,
        clamped: true,
        preload: false,
        x: None,
        y: None,
        z: None,
        normal: None,
    });
    let boundaries = top.chain(bottom).collect();
    Ok(SceneSpec {
        granular: None,
        bodies,
        mesh_bodies: Vec::new(),
        interfaces,
        boundaries,
        ..spec.clone()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::registry;

    fn small() -> SceneSpec {
        registry::builtin("granular-small").expect("registered")
    }

    fn table(spec: &mut SceneSpec) -> &mut GranularSpec {
        spec.granular.as_mut().expect("granular")
    }

    #[test]
    fn the_same_seed_gives_the_same_scene_and_another_seed_another_layout() {
        let spec = small();
        let a = expand(&spec, "test").expect("expands");
        let b = expand(&spec, "test").expect("expands");
        assert_eq!(a, b);
        let mut other = spec.clone();
        table(&mut other).seed = 2;
        let c = expand(&other, "test").expect("expands");
        let grains = |s: &SceneSpec| -> Vec<String> {
            s.bodies
                .iter()
                .filter(|b| b.name.starts_with('G'))
                .map(|b| b.name.clone())
                .collect()
        };
        assert_eq!(grains(&a).len(), grains(&b).len());
        assert_ne!(grains(&a), grains(&c), "seeds 1 and 2 give the same grains");
    }

    /// Grains have sizes within `grain_cells`, are face-connected and never face-adjacent to
    /// another grain, for many seeds and both built-in sizes.
    #[test]
    fn grains_are_connected_separated_and_sized() {
        for (name, sizes) in [("granular-small", [1, 3]), ("granular-paper", [2, 2])] {
            let spec = registry::builtin(name).expect("registered");
            for seed in 0..50 {
                let mut g = spec.granular.clone().expect("granular");
                g.seed = seed;
                let l = layout(&g, name).expect("places");
                assert_eq!(l.grains.len(), g.grains);
                for (n, cells) in l.grains.iter().enumerate() {
                    assert!(
                        (sizes[0]..=sizes[1]).contains(&cells.len()),
                        "{name} {seed}"
                    );
                    // connected: every cell after the first touches an earlier one
                    for (i, &c) in cells.iter().enumerate().skip(1) {
                        assert!(cells[..i].iter().any(|d| l.neighbours(c).contains(d)));
                    }
                    for &c in cells {
                        assert_eq!(l.grain_of[c], Some(n));
                        for d in l.neighbours(c) {
                            assert!(l.grain_of[d].is_none_or(|e| e == n), "{name} {seed}");
                        }
                    }
                }
                let grain_cells = l.grain_of.iter().filter(|g| g.is_some()).count();
                let listed: usize = l.grains.iter().map(Vec::len).sum();
                assert_eq!(grain_cells, listed);
            }
        }
    }

    #[test]
    fn cell_names_and_coordinates() {
        let spec = expand(&small(), "test").expect("expands");
        assert_eq!(spec.bodies.len(), 64);
        let b = &spec.bodies[1 + 4 * (2 + 4 * 3)];
        assert!(b.name.ends_with("[1,2,3]"), "{}", b.name);
        let close = |x: [f64; 3], y: [f64; 3]| (0..3).all(|a| (x[a] - y[a]).abs() < 1e-15);
        assert!(close(b.min, [0.025, 0.05, 0.075]), "{:?}", b.min);
        assert!(close(b.max, [0.05, 0.075, 0.1]), "{:?}", b.max);
        // the cube's far corner is exactly L
        assert_eq!(spec.bodies[63].max, [0.1; 3]);
        assert_eq!(b.divisions, [3, 3, 3]);
        assert!(spec.bodies.iter().all(|b| {
            let grain = b.name.starts_with('G');
            (grain && b.material == "grain") || (b.name.starts_with("M[") && b.material == "matrix")
        }));
        // the top boundary ramps −V0 over 10 steps of 1 µs
        let z = spec.boundaries[0].z.as_ref().expect("z prescribed");
        assert_eq!(z.velocity, Some(-10.0));
        assert!((z.ramp_time - 10e-6).abs() < 1e-18);
    }

    /// `lopin export-scene` writes a granular scene as its `[granular]` table, which reads back
    /// to the same scene.
    #[test]
    fn granular_scenes_round_trip_through_toml() {
        for name in ["granular-small", "granular-paper"] {
            let spec = registry::builtin(name).expect("registered");
            let text = crate::scene::to_toml(&spec);
            assert!(text.contains("[granular]"), "{text}");
            assert!(!text.contains("[[body]]"), "{text}");
            let back = crate::scene::from_toml(&text, name).expect("reads back");
            assert_eq!(back, spec);
        }
    }

    #[test]
    fn refine_multiplies_the_cell_mesh_and_split_is_rejected() {
        let mut spec = small();
        spec.refine(2).expect("refine");
        assert_eq!(table(&mut spec).cell_elements, 6);
        spec.split(1).expect("split");
        assert!(validate(&spec, "test").is_ok());
        spec.split(2).expect("split");
        let msg = validate(&spec, "scene granular-small")
            .expect_err("split")
            .to_string();
        assert!(msg.contains("scene granular-small"), "{msg}");
        assert!(msg.contains("--split 2"), "{msg}");
    }

    /// Each malformed table gives an error naming the source, the field and the reason.
    #[test]
    fn malformed_tables_get_clear_errors() {
        type Edit = fn(&mut SceneSpec);
        let cases: [(&str, Edit, &str, &str); 12] = [
            (
                "zero in grid",
                |s| table(s).grid = [4, 0, 4],
                "granular.grid",
                "y: must be at least 1 cell",
            ),
            (
                "negative side",
                |s| table(s).side = -1.0,
                "granular.side",
                "positive",
            ),
            (
                "no elements",
                |s| table(s).cell_elements = 0,
                "granular.cell_elements",
                "at least 1",
            ),
            (
                "unknown grain material",
                |s| table(s).grain = "basalt".into(),
                "granular.grain",
                "no material named `basalt`",
            ),
            (
                "unknown matrix material",
                |s| table(s).matrix = "mortar".into(),
                "granular.matrix",
                "no material named `mortar`",
            ),
            (
                "more grain cells than cells",
                |s| {
                    table(s).grains = 40;
                    table(s).grain_cells = [2, 3];
                },
                "granular.grains",
                "do not fit in 64 cells",
            ),
            (
                "grains that fit in count but not apart",
                |s| table(s).grains = 30,
                "granular.grains",
                "found no room for grain",
            ),
            (
                "min above max",
                |s| table(s).grain_cells = [3, 2],
                "granular.grain_cells",
                "minimum 3 exceeds maximum 2",
            ),
            (
                "empty grains",
                |s| table(s).grain_cells = [0, 2],
                "granular.grain_cells",
                "at least 1 cell",
            ),
            (
                "negative friction",
                |s| table(s).friction = -0.1,
                "granular.friction",
                "lies in [0, 10]",
            ),
            (
                "no ramp",
                |s| table(s).ramp_steps = 0,
                "granular.ramp_steps",
                "at least 1 step",
            ),
            (
                "explicit bodies",
                |s| {
                    let g = expand(s, "test").expect("expands");
                    s.bodies = g.bodies[..2].to_vec();
                },
                "body",
                "remove the 2 [[body]] entries",
            ),
        ];
        for (what, edit, field, reason) in cases {
            let mut spec = small();
            edit(&mut spec);
            let err = crate::scene::check(&spec, "bad.toml").expect_err(what);
            let msg = err.to_string();
            assert!(matches!(err, LopinError::Scene { .. }), "{what}: {msg}");
            assert!(msg.contains("bad.toml"), "{what}: no source in `{msg}`");
            assert!(
                msg.contains(&format!("`{field}`")),
                "{what}: no field `{field}` in `{msg}`"
            );
            assert!(
                msg.contains(reason),
                "{what}: no reason `{reason}` in `{msg}`"
            );
        }
    }
}
