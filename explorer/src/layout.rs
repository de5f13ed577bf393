//! How the scene is drawn: the view options (coloured quantity, colour range, deformation,
//! exploded view, section), the camera, the drawn mesh (rebuilt when the fields on screen, the
//! configuration compared with them or an option change) and, side by side, the pinned
//! configuration's mesh on the colour range both share; and where the 3D view (one viewport or
//! two) and the controls a script clicks were drawn in the last frame.

use crate::camera::Camera;
use crate::colormap::Range;
use crate::field_cache::FieldCache;
use crate::geometry::SceneGeometry;
use crate::mesh_build::{self, MeshData, MeshInputs};
use crate::quantity::Quantity;
use crate::section::Section;
use crate::study_view::Drawn;
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

/// Mesh versions are unique across scenes: the GPU resources outlive a scene change.
static MESH_VERSION: AtomicU64 = AtomicU64::new(1);

/// View options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewOptions {
    /// Coloured quantity.
    pub quantity: Quantity,
    /// Fixed colour range instead of automatic.
    pub fixed_range: bool,
    /// The fixed range, display units.
    pub range_min: f64,
    /// The fixed range, display units.
    pub range_max: f64,
    /// Draw the deformed shape.
    pub deformed: bool,
    /// Deformation scale factor.
    pub deform_scale: f32,
    /// Pull substructures apart.
    pub exploded: bool,
    /// How far (fraction of each substructure's distance from the centre).
    pub explode_amount: f32,
    /// Show a section.
    pub section: bool,
    /// Section axis 0, 1, 2.
    pub section_axis: usize,
    /// Section position as a fraction of the scene's extent along the axis.
    pub section_fraction: f32,
}

impl Default for ViewOptions {
    fn default() -> Self {
        ViewOptions {
            quantity: Quantity::VonMises,
            fixed_range: false,
            range_min: 0.0,
            range_max: 1.0,
            deformed: false,
            deform_scale: 100.0,
            exploded: false,
            explode_amount: 0.35,
            section: false,
            section_axis: 1,
            section_fraction: 0.5,
        }
    }
}

/// What the current configuration is drawn against: the pinned one's picture at the same step,
/// subtracted or beside it.
#[derive(Debug, Clone, Copy)]
pub enum Against<'a> {
    /// The current configuration alone.
    Nothing,
    /// The difference field: current − this.
    Minus(&'a Drawn),
    /// This one in a second viewport, both on the colour range they share.
    Beside(&'a Drawn),
}

impl Against<'_> {
    /// How it enters the mesh key: a kind and the fields' address.
    fn key(&self) -> (u8, usize) {
        let at = |d: &Drawn| Arc::as_ptr(&d.0) as usize;
        match self {
            Against::Nothing => (0, 0),
            Against::Minus(d) => (1, at(d)),
            Against::Beside(d) => (2, at(d)),
        }
    }
}

/// Where some controls were drawn in the last frame, points: "friction" and "time" (slider
/// rails), "section" and "exploded" (checkboxes), "pin A" (button) and "side by side" (radio
/// button). Scripts driving the web page click there.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ControlRects(BTreeMap<&'static str, egui::Rect>);

impl ControlRects {
    /// Notes where control `name` was drawn.
    pub fn place(&mut self, name: &'static str, rect: egui::Rect) {
        self.0.insert(name, rect);
    }

    /// Where control `name` was drawn.
    pub fn get(&self, name: &str) -> Option<egui::Rect> {
        self.0.get(name).copied()
    }

    /// Every control drawn, by name.
    pub fn iter(&self) -> impl Iterator<Item = (&'static str, egui::Rect)> + '_ {
        self.0.iter().map(|(k, r)| (*k, *r))
    }
}

/// View options, camera, drawn mesh and where things were drawn.
pub struct Layout {
    /// View options (edited by the left panel).
    pub view: ViewOptions,
    /// The camera (moved by the 3D view).
    pub camera: Camera,
    /// Where the controls a script clicks were drawn in the last frame.
    pub controls: ControlRects,
    /// The camera that frames the scene (double-click, "reset view").
    home: Camera,
    /// Drawn mesh.
    mesh: Arc<MeshData>,
    /// Its version, unique across scenes.
    mesh_version: u64,
    /// The pinned configuration's mesh and its version, drawn beside the current one.
    beside: Option<(Arc<MeshData>, u64)>,
    /// What the drawn meshes were built from: fields, contact histories, what they are drawn
    /// against, options.
    mesh_key: Option<(usize, usize, (u8, usize), MeshInputs)>,
    /// Where the 3D view (the current configuration's viewport) was drawn in the last frame,
    /// points.
    view_rect: Option<egui::Rect>,
    /// Where the pinned configuration's viewport was drawn in the last frame (side by side).
    beside_rect: Option<egui::Rect>,
}

/// A new mesh version, unique across scenes.
fn next_version() -> u64 {
    MESH_VERSION.fetch_add(1, Ordering::Relaxed)
}

impl Layout {
    /// Default view options, the camera framing the scene's bounding box, nothing drawn yet.
    pub fn new(geometry: &SceneGeometry) -> Layout {
        let home = Camera::framing(geometry.lo, geometry.hi);
        Layout {
            view: ViewOptions::default(),
            camera: home,
            controls: ControlRects::default(),
            home,
            mesh: Arc::new(MeshData::default()),
            mesh_version: 0,
            beside: None,
            mesh_key: None,
            view_rect: None,
            beside_rect: None,
        }
    }

    /// Frames the whole scene again.
    pub fn reset_camera(&mut self) {
        self.camera = self.home;
    }

    /// The drawn mesh.
    pub fn mesh(&self) -> &Arc<MeshData> {
        &self.mesh
    }

    /// Version of the drawn mesh, new at each rebuild.
    pub fn mesh_version(&self) -> u64 {
        self.mesh_version
    }

    /// The pinned configuration's mesh and its version, when it is drawn beside the current
    /// one and has a picture at the displayed step.
    pub fn beside(&self) -> Option<(&Arc<MeshData>, u64)> {
        self.beside.as_ref().map(|(m, v)| (m, *v))
    }

    /// Where the 3D view (the current configuration's viewport) was drawn in the last frame,
    /// points.
    pub fn view_rect(&self) -> Option<egui::Rect> {
        self.view_rect
    }

    /// Where the pinned configuration's viewport was drawn in the last frame, points (None:
    /// one viewport).
    pub fn beside_rect(&self) -> Option<egui::Rect> {
        self.beside_rect
    }

    /// Notes where the current configuration's viewport and, side by side, the pinned one's
    /// are drawn.
    pub fn set_view_rects(&mut self, view: egui::Rect, beside: Option<egui::Rect>) {
        self.view_rect = Some(view);
        self.beside_rect = beside;
    }

    /// The section plane of the current options.
    pub fn section(&self, geometry: &SceneGeometry) -> Option<Section> {
        self.view.section.then(|| {
            let a = self.view.section_axis;
            let (lo, hi) = (geometry.lo[a], geometry.hi[a]);
            let position = lo + (hi - lo) * self.view.section_fraction;
            Section {
                axis: a,
                position,
                // cut away the half on the camera's side, so the cut face looks at the viewer
                facing: if self.camera.eye()[a] > position {
                    1.0
                } else {
                    -1.0
                },
            }
        })
    }

    fn mesh_inputs(&self, geometry: &SceneGeometry) -> MeshInputs {
        let v = &self.view;
        MeshInputs {
            quantity: v.quantity,
            range: if v.fixed_range {
                Range::Fixed {
                    min: v.range_min,
                    max: v.range_max,
                }
            } else {
                Range::Auto
            },
            deform: if v.deformed { v.deform_scale } else { 0.0 },
            explode: if v.exploded { v.explode_amount } else { 0.0 },
            section: self.section(geometry),
        }
    }

    /// Rebuilds the drawn meshes if the fields on screen, the contact histories, what they are
    /// drawn `against` (the pinned configuration subtracted, or beside them) or the options
    /// changed since the last build. Side by side, both meshes are coloured on the range they
    /// share ([`mesh_build::shared_range`]). Returns whether it rebuilt.
    pub fn rebuild_mesh_if_needed(
        &mut self,
        geometry: &SceneGeometry,
        cache: &FieldCache,
        against: Against<'_>,
    ) -> bool {
        if !matches!(against, Against::Beside(_)) {
            self.beside = None;
        }
        let Some(f) = cache.shown() else {
            return false;
        };
        let inputs = self.mesh_inputs(geometry);
        let key = (
            Arc::as_ptr(f) as usize,
            cache.contact().map_or(0, |c| Arc::as_ptr(c) as usize),
            against.key(),
            inputs,
        );
        if self.mesh_key == Some(key) {
            return false;
        }
        let contact = cache.contact().map(|c| c.as_slice());
        match against {
            Against::Beside(d) => {
                let pinned = (d.0.as_ref(), Some(d.1.as_slice()));
                let (min, max) = mesh_build::shared_range(
                    geometry,
                    (f, contact),
                    pinned,
                    inputs.range,
                    inputs.quantity,
                );
                let shared = MeshInputs {
                    range: Range::Fixed { min, max },
                    ..inputs
                };
                self.mesh = Arc::new(mesh_build::build(geometry, f, contact, &shared, None));
                let beside = mesh_build::build(geometry, pinned.0, pinned.1, &shared, None);
                self.beside = Some((Arc::new(beside), next_version()));
            }
            Against::Minus(d) => {
                let minus = (d.0.as_ref(), Some(d.1.as_slice()));
                self.mesh = Arc::new(mesh_build::build(
                    geometry,
                    f,
                    contact,
                    &inputs,
                    Some(minus),
                ));
            }
            Against::Nothing => {
                self.mesh = Arc::new(mesh_build::build(geometry, f, contact, &inputs, None));
            }
        }
        self.mesh_version = next_version();
        self.mesh_key = Some(key);
        true
    }
}
