//! How the scene is drawn: the view options (coloured quantity, colour range, deformation,
//! exploded view, section), the camera, the drawn mesh (rebuilt when the fields on screen, the
//! configuration subtracted from them or an option change), and where the 3D view and the controls a script clicks were drawn in the last
//! frame.

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

/// Where some controls were drawn in the last frame, points: "friction" and "time" (slider
/// rails), "section" and "exploded" (checkboxes). Scripts driving the web page click there.
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
    /// What the drawn mesh was built from: fields, contact histories, the fields subtracted,
    /// options.
    mesh_key: Option<(usize, usize, usize, MeshInputs)>,
    /// Where the 3D view was drawn in the last frame, points.
    view_rect: Option<egui::Rect>,
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
            mesh_key: None,
            view_rect: None,
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

    /// Where the 3D view was drawn in the last frame, points.
    pub fn view_rect(&self) -> Option<egui::Rect> {
        self.view_rect
    }

    /// Notes where the 3D view is drawn.
    pub fn set_view_rect(&mut self, rect: egui::Rect) {
        self.view_rect = Some(rect);
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

    /// Rebuilds the drawn mesh if the fields on screen, the contact histories, the
    /// configuration subtracted (`minus`: the difference field) or the options changed since
    /// the last build. Returns whether it rebuilt.
    pub fn rebuild_mesh_if_needed(
        &mut self,
        geometry: &SceneGeometry,
        cache: &FieldCache,
        minus: Option<&Drawn>,
    ) -> bool {
        let Some(f) = cache.shown() else {
            return false;
        };
        let inputs = self.mesh_inputs(geometry);
        let key = (
            Arc::as_ptr(f) as usize,
            cache.contact().map_or(0, |c| Arc::as_ptr(c) as usize),
            minus.map_or(0, |m| Arc::as_ptr(&m.0) as usize),
            inputs,
        );
        if self.mesh_key == Some(key) {
            return false;
        }
        let contact = cache.contact().map(|c| c.as_slice());
        let minus = minus.map(|(f, c)| (f.as_ref(), Some(c.as_slice())));
        self.mesh = Arc::new(mesh_build::build(geometry, f, contact, &inputs, minus));
        self.mesh_version = MESH_VERSION.fetch_add(1, Ordering::Relaxed);
        self.mesh_key = Some(key);
        true
    }
}
