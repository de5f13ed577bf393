//! The one door from a scene to a built problem: [`open`] reads the scene (a registry name, a
//! file or a description in memory, [`Source`]), applies the [`Overrides`] of the command line
//! or the explorer (refinement, split, the settings layer, parameter values), expands a
//! generator table, validates, admits the solve's size and builds, each exactly once, and
//! returns the problem with its resolved [`Settings`] ([`Opened`]). [`admit`] stops before the
//! build (a size estimate, or a refusal with the numbers); [`check`] validates a scene without
//! building it (what [`load`] and [`from_toml`] do to what they read).
//!
//! The order is the order of cost: the table of a generator is checked and the solve it asks
//! for admitted before the table is expanded into one body per cell (or meshed by gmsh); a
//! listed scene is validated before it is admitted; mesh bodies are admitted again once their
//! files are read ([`super::build`]).

use crate::error::{LopinError, Result};
use crate::problem::Problem;
use crate::scene::admission::{self, Footprint, SolveShape};
use crate::scene::spec::{SceneSpec, SolverSpec};
use crate::scene::validate::{validate_expanded, Generated};
use crate::scene::{build, granular, granular_poly};
use crate::scene::{reading, registry};
use crate::settings::Settings;
use crate::target::Assignment;
use crate::window_choice::{choose, Task, WindowChoice};

/// Where a scene comes from.
#[derive(Debug, Clone)]
pub enum Source {
    /// A built-in or test scene's name, or a path to a TOML file.
    Named(String),
    /// A description in memory; `label` names it in errors.
    Spec {
        /// The description.
        spec: Box<SceneSpec>,
        /// How errors name it.
        label: String,
    },
}

impl Source {
    /// A description in memory, named `label` in errors.
    pub fn spec(spec: SceneSpec, label: &str) -> Self {
        Self::Spec {
            spec: Box::new(spec),
            label: label.to_string(),
        }
    }

    /// How errors name the scene: `scene NAME` for a built-in, else the path or the label.
    pub fn label(&self) -> String {
        match self {
            Self::Named(n) => source_label(n),
            Self::Spec { label, .. } => label.clone(),
        }
    }

    /// The description as written (parsed, not yet checked).
    fn read(self) -> Result<SceneSpec> {
        match self {
            Self::Named(n) => read(&n),
            Self::Spec { spec, .. } => Ok(*spec),
        }
    }
}

impl From<&str> for Source {
    fn from(name_or_path: &str) -> Self {
        Self::Named(name_or_path.to_string())
    }
}

impl From<&String> for Source {
    fn from(name_or_path: &String) -> Self {
        Self::Named(name_or_path.clone())
    }
}

impl From<SceneSpec> for Source {
    /// A description in memory, named `scene NAME` after its `name` field.
    fn from(spec: SceneSpec) -> Self {
        let label = format!("scene {}", spec.name);
        Self::spec(spec, &label)
    }
}

/// What the command line or the explorer changes of a scene as written.
#[derive(Debug, Clone, PartialEq)]
pub struct Overrides {
    /// Multiply the mesh divisions by this (≥ 1).
    pub refine: usize,
    /// Multiply the substructures per body by this (≥ 1).
    pub split: usize,
    /// The settings layer over the scene's `[solver]` table.
    pub solver: SolverSpec,
    /// What the solve is for, which picks the windows when nobody asked.
    pub task: Task,
    /// Parameter values set on the built problem, in order.
    pub assignments: Vec<Assignment>,
}

impl Default for Overrides {
    fn default() -> Self {
        Self {
            refine: 1,
            split: 1,
            solver: SolverSpec::default(),
            task: Task::Single,
            assignments: Vec::new(),
        }
    }
}

impl Overrides {
    /// No change, for a solve of `task`.
    pub fn for_task(task: Task) -> Self {
        Self {
            task,
            ..Self::default()
        }
    }

    /// The scene's `[solver]` table under this layer.
    pub fn layer(&self, spec: &SceneSpec) -> SolverSpec {
        self.solver.over(&spec.solver)
    }

    /// The time windows of a solve of `spec` and why ([`choose`]).
    pub fn windows(&self, spec: &SceneSpec) -> WindowChoice {
        choose(
            self.task,
            self.solver.window,
            spec.solver.window,
            spec.has_contact(),
        )
    }

    /// How the solve will run, as far as memory is concerned.
    pub fn shape(&self, spec: &SceneSpec) -> SolveShape {
        SolveShape {
            window: self.windows(spec).window,
            two_scale: self.layer(spec).two_scale.unwrap_or(false),
            skip_unchanged: true,
        }
    }
}

/// A scene read, resized, validated and admitted: what it will hold is known and fits.
#[derive(Debug, Clone)]
pub struct Admitted {
    /// The scene as written, after `refine` and `split`.
    pub spec: SceneSpec,
    /// How errors name it.
    pub source: String,
    /// The sizes and memory of the solve, counted before anything large is built.
    pub footprint: Footprint,
    /// The scene its generator table expanded into (None: the scene lists its bodies).
    expanded: Option<SceneSpec>,
    overrides: Overrides,
}

/// A scene opened: its problem built and its settings resolved.
#[derive(Debug)]
pub struct Opened {
    /// The scene as written, after `refine` and `split` (its parameter values as written: the
    /// assignments are on the problem).
    pub spec: SceneSpec,
    /// How errors name it.
    pub source: String,
    /// The sizes and memory of the solve, counted before building.
    pub footprint: Footprint,
    /// The discrete problem, with the assignments applied.
    pub problem: Problem,
    /// Every solver setting: defaults < the scene's `[solver]` < the overrides.
    pub settings: Settings,
    /// The time windows chosen and why.
    pub windows: WindowChoice,
    /// The parameter values set on the problem.
    pub assignments: Vec<Assignment>,
}

/// Reads, expands, validates, admits and builds a scene, each once.
pub fn open(source: impl Into<Source>, overrides: &Overrides) -> Result<Opened> {
    admit(source, overrides)?.build()
}

/// [`open`] up to the build: the scene read, resized, expanded, validated and admitted.
pub fn admit(source: impl Into<Source>, overrides: &Overrides) -> Result<Admitted> {
    let source = source.into();
    let label = source.label();
    let mut spec = source.read()?;
    if overrides.refine == 0 || overrides.split == 0 {
        let field = if overrides.refine == 0 {
            "refine"
        } else {
            "split"
        };
        return Err(LopinError::setting(field, "must be at least 1"));
    }
    spec.refine(overrides.refine)?;
    spec.split(overrides.split)?;
    let shape = overrides.shape(&spec);
    let (expanded, footprint) = expand_checked(&spec, &label, shape)?;
    Ok(Admitted {
        spec,
        source: label,
        footprint,
        expanded,
        overrides: overrides.clone(),
    })
}

impl Admitted {
    /// Builds the problem, applies the parameter values and resolves the settings.
    pub fn build(self) -> Result<Opened> {
        let windows = self.overrides.windows(&self.spec);
        let layer = self.overrides.layer(&self.spec);
        let rho_inf = layer.rho_inf.unwrap_or(1.0);
        let listed = self.expanded.as_ref().unwrap_or(&self.spec);
        let mut problem = build::build_expanded(listed, &self.source, rho_inf)?;
        let mut settings = Settings::for_problem(&problem, &layer);
        settings.window = windows.window;
        for a in &self.overrides.assignments {
            a.apply(&mut problem)?;
        }
        Ok(Opened {
            spec: self.spec,
            source: self.source,
            footprint: self.footprint,
            problem,
            settings,
            windows,
            assignments: self.overrides.assignments,
        })
    }
}

/// Validates a scene as [`open`] does, without building it (a `[granular_poly]` table is
/// checked as a table: its sample is meshed when the scene is opened).
pub fn check(spec: &SceneSpec, source: &str) -> Result<()> {
    if spec.granular_poly.is_some() {
        return granular_poly::validate(spec, source);
    }
    expand_checked(spec, source, SolveShape::smallest()).map(|_| ())
}

/// The scene a generator table expands to (None: the scene lists its bodies), validated, and
/// the footprint of a solve of `shape`: a generator table is checked and admitted before it is
/// expanded.
fn expand_checked(
    spec: &SceneSpec,
    source: &str,
    shape: SolveShape,
) -> Result<(Option<SceneSpec>, Footprint)> {
    if spec.granular_poly.is_some() {
        if cfg!(not(feature = "msh")) {
            // nothing to mesh the sample with: refused before any grain is placed
            return Err(LopinError::scene(
                source,
                "granular_poly",
                granular_poly::NOT_MESHED,
            ));
        }
        let grains = granular_poly::placed_grains(spec, source)?;
        let footprint = admission::admit(spec, source, shape)?;
        let expanded = granular_poly::expand_placed(spec, source, &grains)?;
        validate_expanded(&expanded, source, Generated::No)?;
        return Ok((Some(expanded), footprint));
    }
    if spec.granular.is_some() {
        granular::validate(spec, source)?;
        let footprint = admission::admit(spec, source, shape)?;
        let expanded = granular::expand(spec, source)?;
        validate_expanded(&expanded, source, Generated::Yes).map_err(generated_field)?;
        return Ok((Some(expanded), footprint));
    }
    validate_expanded(spec, source, Generated::No)?;
    let footprint = admission::admit(spec, source, shape)?;
    Ok((None, footprint))
}

/// An error on a body, interface or boundary a `[granular]` table generated says so.
fn generated_field(e: LopinError) -> LopinError {
    match e {
        LopinError::Scene {
            source_name,
            field,
            reason,
        } if ["body", "interface", "boundary"]
            .iter()
            .any(|p| field.starts_with(p)) =>
        {
            LopinError::Scene {
                source_name,
                field: format!("granular (generated {field})"),
                reason,
            }
        }
        other => other,
    }
}

/// How errors name a scene given to [`read`]: `scene NAME` for a built-in, else the path.
pub fn source_label(name_or_path: &str) -> String {
    if registry::contains(name_or_path) {
        format!("scene {name_or_path}")
    } else {
        name_or_path.to_string()
    }
}

/// Reads a scene, unchecked ([`load`] checks it): a registry name (built-in or
/// test scene), or a path to a TOML file (not on wasm32, which has no files).
pub fn read(name_or_path: &str) -> Result<SceneSpec> {
    if let Some(text) = registry::source(name_or_path) {
        return reading::parse(text, &format!("scene {name_or_path}"));
    }
    #[cfg(not(target_arch = "wasm32"))]
    {
        let path = std::path::Path::new(name_or_path);
        if path.exists() {
            let text = std::fs::read_to_string(path).map_err(|e| LopinError::Io {
                path: name_or_path.to_string(),
                reason: e.to_string(),
            })?;
            let mut spec = reading::parse(&text, name_or_path)?;
            super::time_tables::read_files(&mut spec, name_or_path)?;
            return Ok(spec);
        }
    }
    Err(LopinError::UnknownScene {
        name: name_or_path.to_string(),
        known: registry::SCENES.join(", "),
    })
}

/// Reads a scene and checks it ([`check`]): a registry name, or a path to a TOML file (not on
/// wasm32, which has no files).
pub fn load(name_or_path: &str) -> Result<SceneSpec> {
    let spec = read(name_or_path)?;
    check(&spec, &source_label(name_or_path))?;
    Ok(spec)
}

/// Parses a scene from TOML text and checks it ([`check`]); `source` (usually the file path)
/// names it in errors.
pub fn from_toml(text: &str, source: &str) -> Result<SceneSpec> {
    let spec = reading::parse(text, source)?;
    check(&spec, source)?;
    Ok(spec)
}

/// The built problem of a description in memory, with its own settings (a shorthand of
/// [`open`] without overrides, for examples and tests).
pub fn problem_of(spec: &SceneSpec, label: &str) -> Result<Problem> {
    open(Source::spec(spec.clone(), label), &Overrides::default()).map(|o| o.problem)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parameter::Parameter;
    use crate::scene::registry;
    use crate::window_choice::WindowRequest;

    /// The one precedence rule: the defaults of METHOD §10, under the scene's `[solver]` table,
    /// under the overrides; ρ∞ reaches the problem's scheme, and the windows follow the task
    /// unless someone asked.
    #[test]
    fn settings_resolve_defaults_then_scene_then_overrides() {
        let mut spec = registry::builtin("mini-blocks").expect("scene");
        let plain = open(spec.clone(), &Overrides::default()).expect("opens");
        let k0 = plain.problem.default_k();
        assert_eq!(
            (plain.settings.k, plain.settings.mu, plain.settings.tol),
            (k0, 0.8, 1e-3)
        );
        assert_eq!(plain.settings.rho_inf, 1.0);
        // one cold solve of a scene with contact: one-step windows
        assert_eq!(plain.settings.window, Some(1));
        spec.solver.mu = Some(0.5);
        spec.solver.tol = Some(1e-4);
        spec.solver.rho_inf = Some(0.7);
        let scene_only = open(spec.clone(), &Overrides::default()).expect("opens");
        assert_eq!(
            (scene_only.settings.mu, scene_only.settings.tol),
            (0.5, 1e-4)
        );
        assert_eq!(scene_only.problem.scheme.rho_inf, 0.7);
        let over = Overrides {
            solver: SolverSpec {
                mu: Some(0.9),
                rho_inf: Some(0.6),
                window: Some(WindowRequest::Whole),
                ..SolverSpec::default()
            },
            ..Overrides::default()
        };
        let both = open(spec, &over).expect("opens");
        assert_eq!((both.settings.mu, both.settings.tol), (0.9, 1e-4));
        assert_eq!(
            (both.settings.rho_inf, both.problem.scheme.rho_inf),
            (0.6, 0.6)
        );
        assert_eq!(both.settings.window, None);
        // a scene with contact: one-step windows in the explorer too
        let explorer = open("mini-blocks", &Overrides::for_task(Task::Interactive)).expect("opens");
        assert!(explorer.problem.contact_count() > 0);
        assert_eq!(explorer.settings.window, Some(1));
    }

    /// Parameter values go through `Parameter` onto the built problem (on every contact, or on
    /// one zone), and the scene as written keeps its own.
    #[test]
    fn assignments_set_parameters_on_the_built_problem() {
        let spec = registry::builtin("mini-blocks").expect("scene");
        let written = Parameter::Friction.current(&problem_of(&spec, "mini").expect("builds"));
        let over = Overrides {
            assignments: vec![
                Assignment::parse("f=0.45").expect("f"),
                Assignment::parse("gap=2e-6").expect("gap"),
            ],
            ..Overrides::default()
        };
        let opened = open(spec.clone(), &over).expect("opens");
        assert_eq!(Parameter::Friction.current(&opened.problem), Some(0.45));
        assert_eq!(Parameter::Gap.current(&opened.problem), Some(2e-6));
        assert_eq!(opened.spec, spec, "the scene as written is kept");
        assert_ne!(written, Some(0.45));
        let unknown = Overrides {
            assignments: vec![Assignment::parse("f@nowhere=0.2").expect("parses")],
            ..Overrides::default()
        };
        let e = open(spec, &unknown).expect_err("no zone").to_string();
        assert!(e.contains("nowhere") && e.contains("[[zone]]"), "{e}");
    }

    /// Resizing, validation and admission happen before the build: a refused refinement
    /// names itself, a bad field names the file and field, and a request too large for the
    /// machine is refused with the numbers, without building anything.
    #[test]
    fn the_door_refuses_before_building() {
        let e = admit(
            "mini-blocks",
            &Overrides {
                refine: 0,
                ..Overrides::default()
            },
        )
        .expect_err("refine 0")
        .to_string();
        assert!(e.contains("refine"), "{e}");
        let mut spec = registry::builtin("mini-blocks").expect("scene");
        spec.materials[0].poisson = 0.7;
        let e = open(Source::spec(spec, "bad.toml"), &Overrides::default())
            .expect_err("poisson")
            .to_string();
        assert!(
            e.contains("bad.toml") && e.contains("material[0].poisson"),
            "{e}"
        );
        let huge = Overrides {
            refine: 400,
            ..Overrides::default()
        };
        let e = admit("two-blocks", &huge).expect_err("too large");
        assert!(matches!(e, LopinError::TooLarge { .. }), "{e}");
        let admitted = admit("mini-blocks", &Overrides::default()).expect("fits");
        assert_eq!(admitted.footprint.substructures, 2);
        let built = admitted.build().expect("builds");
        assert_eq!(built.problem.subs.len(), 2);
        assert_eq!(built.footprint.dofs, built.problem.dof_count());
    }
}
