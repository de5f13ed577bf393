//! The 3D view widget: one viewport, or two side by side (the pinned configuration A on the
//! left, the current one on the right, each labelled with its parameter value) moved by one
//! camera: mouse orbit (drag), pan (right or middle drag, or shift-drag), zoom (scroll), reset
//! (double-click) in either, picking a probe node (click, in the current configuration's
//! viewport), one wgpu paint callback per viewport, the colour legend with quantity, unit, range
//! and min/max (diverging for a difference field; side by side both legends show the range they
//! share), and a note over the view (what is shown while a re-solve refines it, what is
//! compared).

use crate::colormap;
use crate::geometry::SceneGeometry;
use crate::layout::{Layout, ViewOptions};
use crate::mesh_build::{self, MeshData};
use crate::render::{SceneCallback, Uniforms};
use eframe::egui_wgpu;
use egui::{Color32, Pos2, Rect, Sense, Stroke, Vec2};
use std::sync::Arc;

const BACKGROUND: [f32; 3] = [0.105, 0.11, 0.125];
/// Points between the two viewports side by side.
const GAP: f32 = 4.0;

/// The labels of the two viewports side by side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SideBySide<'a> {
    /// The pinned configuration's, as "A: f = 0.300".
    pub a: &'a str,
    /// The current configuration's, as "B: f = 0.250".
    pub b: &'a str,
}

/// The two viewports side by side in `rect`: A's on the left, the current one's on the right,
/// of equal size.
pub fn halves(rect: Rect) -> (Rect, Rect) {
    let w = ((rect.width() - GAP) * 0.5).max(1.0);
    let left = Rect::from_min_size(rect.min, Vec2::new(w, rect.height()));
    let right = Rect::from_min_max(Pos2::new(rect.max.x - w, rect.min.y), rect.max);
    (left, right)
}

/// Draws the 3D view of `layout`'s mesh in the remaining space (with the wgpu renderer when
/// `gpu`), with `note` in the current configuration's top-left corner, and moves its camera;
/// with `side`, the remaining space is split and the pinned configuration's mesh
/// ([`Layout::beside`]) is drawn on the left with the same camera. Returns the node a click
/// picked (substructure, node).
pub fn show(
    ui: &mut egui::Ui,
    layout: &mut Layout,
    geometry: &SceneGeometry,
    gpu: bool,
    note: Option<&str>,
    side: Option<SideBySide<'_>>,
) -> Option<(usize, usize)> {
    let full = ui.available_rect_before_wrap();
    let Some(side) = side else {
        layout.set_view_rects(full, None);
        let response = input(ui, layout, full, "3D view");
        let picked = pick(&response, layout, geometry, full);
        current(ui, layout, full, gpu, note, false);
        return picked;
    };
    let (left, right) = halves(full);
    layout.set_view_rects(right, Some(left));
    // both viewports move the one camera before either is drawn
    input(ui, layout, left, &format!("3D view {}", side.a));
    let response = input(ui, layout, right, &format!("3D view {}", side.b));
    let picked = pick(&response, layout, geometry, right);
    match layout.beside() {
        Some((mesh, version)) => {
            paint_mesh(ui, layout, left, mesh, version, 1, gpu);
            legend(&layout.view, mesh, ui, left, true);
        }
        None => message(ui, left, "no picture of A at this time step yet"),
    }
    caption(ui, left, side.a);
    let note = match note {
        Some(n) => format!("{}\n{n}", side.b),
        None => side.b.to_string(),
    };
    current(ui, layout, right, gpu, Some(&note), true);
    picked
}

/// Allocates a viewport named `name` (for assistive technology and tests) and moves the camera
/// by the mouse over it.
fn input(ui: &mut egui::Ui, layout: &mut Layout, rect: Rect, name: &str) -> egui::Response {
    let response = ui.allocate_rect(rect, Sense::click_and_drag());
    response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Canvas, true, name));
    let pan = response.dragged_by(egui::PointerButton::Secondary)
        || response.dragged_by(egui::PointerButton::Middle)
        || (response.dragged_by(egui::PointerButton::Primary) && ui.input(|i| i.modifiers.shift));
    let d = response.drag_delta();
    if pan {
        layout.camera.pan(d.x, d.y, rect.width(), rect.height());
    } else if response.dragged_by(egui::PointerButton::Primary) {
        layout.camera.orbit(d.x, d.y);
    }
    if response.hovered() {
        let scroll = ui.input(|i| i.smooth_scroll_delta.y);
        if scroll != 0.0 {
            layout.camera.zoom((scroll * 0.002).exp());
        }
    }
    if response.double_clicked() {
        layout.reset_camera();
    }
    response
}

/// The node a click in the current configuration's viewport `rect` picked.
fn pick(
    response: &egui::Response,
    layout: &Layout,
    geometry: &SceneGeometry,
    rect: Rect,
) -> Option<(usize, usize)> {
    if response.double_clicked() || !response.clicked() {
        return None;
    }
    let p = response.interact_pointer_pos()?;
    let ndc_x = 2.0 * (p.x - rect.left()) / rect.width() - 1.0;
    let ndc_y = 1.0 - 2.0 * (p.y - rect.top()) / rect.height();
    let (o, dir) = layout.camera.ray(ndc_x, ndc_y, aspect(rect));
    mesh_build::pick(layout.mesh(), layout.section(geometry), o, dir, geometry)
}

fn aspect(rect: Rect) -> f32 {
    rect.width() / rect.height().max(1.0)
}

/// The current configuration's viewport: its mesh, legend and note.
fn current(
    ui: &egui::Ui,
    layout: &Layout,
    rect: Rect,
    gpu: bool,
    note: Option<&str>,
    shared: bool,
) {
    let mesh = layout.mesh();
    paint_mesh(ui, layout, rect, mesh, layout.mesh_version(), 0, gpu);
    legend(&layout.view, mesh, ui, rect, shared);
    if let Some(note) = note {
        caption(ui, rect, note);
    }
    if mesh.vertices.is_empty() {
        message(ui, rect, "solving…");
    }
}

/// Draws `mesh` (version `version`) into `rect` through viewport slot `slot` of the renderer,
/// with `layout`'s camera and section.
fn paint_mesh(
    ui: &egui::Ui,
    layout: &Layout,
    rect: Rect,
    mesh: &Arc<MeshData>,
    version: u64,
    slot: usize,
    gpu: bool,
) {
    if !gpu {
        message(ui, rect, "The 3D view needs the wgpu renderer.");
        return;
    }
    let ppp = ui.ctx().pixels_per_point();
    let view_proj = layout.camera.view_proj(aspect(rect));
    let light = (layout.camera.eye() - layout.camera.target).normalize_or_zero()
        + glam::Vec3::new(0.3, 0.2, 0.6);
    let cb = SceneCallback {
        slot,
        mesh: mesh.clone(),
        version,
        uniforms: Uniforms {
            view_proj: view_proj.to_cols_array_2d(),
            light: light.extend(0.0).to_array(),
            flags: [if layout.view.section { 1.0 } else { 0.0 }, 0.0, 0.0, 0.0],
        },
        size_px: [
            (rect.width() * ppp).round() as u32,
            (rect.height() * ppp).round() as u32,
        ],
        background: BACKGROUND,
    };
    ui.painter()
        .add(egui_wgpu::Callback::new_paint_callback(rect, cb));
}

/// A centred message over a viewport.
fn message(ui: &egui::Ui, rect: Rect, text: &str) {
    ui.painter_at(rect).text(
        rect.center(),
        egui::Align2::CENTER_CENTER,
        text,
        egui::FontId::proportional(16.0),
        Color32::LIGHT_GRAY,
    );
}

/// Text on a dark box in a viewport's top-left corner.
fn caption(ui: &egui::Ui, rect: Rect, text: &str) {
    let painter = ui.painter_at(rect);
    let font = egui::FontId::proportional(14.0);
    let galley = painter.layout_no_wrap(text.to_string(), font, Color32::WHITE);
    let at = rect.left_top() + Vec2::new(12.0, 10.0);
    painter.rect_filled(
        Rect::from_min_size(at, galley.size()).expand(5.0),
        4.0,
        Color32::from_black_alpha(170),
    );
    painter.galley(at, galley, Color32::WHITE);
}

/// Colour bar of `mesh` in the lower-left corner of viewport `view` (`shared`: its range is the
/// one both viewports side by side share).
fn legend(options: &ViewOptions, mesh: &MeshData, ui: &egui::Ui, view: Rect, shared: bool) {
    let q = options.quantity;
    let (lo, hi) = mesh.range;
    let (min, max) = mesh.extent;
    let painter = ui.painter_at(view);
    let origin = view.left_bottom() + Vec2::new(16.0, -44.0);
    let bar = Rect::from_min_size(origin - Vec2::new(0.0, 150.0), Vec2::new(18.0, 150.0));
    let panel = Rect::from_min_max(
        bar.min - Vec2::new(8.0, 30.0),
        Pos2::new(bar.max.x + 150.0, bar.max.y + 34.0),
    );
    painter.rect_filled(panel, 4.0, Color32::from_black_alpha(150));
    let n = 48;
    for k in 0..n {
        let t0 = k as f32 / n as f32;
        let t1 = (k + 1) as f32 / n as f32;
        let t = f64::from(t0 + t1) * 0.5;
        let c = if mesh.difference {
            colormap::diverging(t, 0.0, 1.0)
        } else {
            colormap::color(t, 0.0, 1.0)
        };
        let r = Rect::from_min_max(
            Pos2::new(bar.min.x, bar.max.y - t1 * bar.height()),
            Pos2::new(bar.max.x, bar.max.y - t0 * bar.height()),
        );
        painter.rect_filled(r, 0.0, rgb(c));
    }
    painter.rect_stroke(
        bar,
        0.0,
        Stroke::new(1.0, Color32::GRAY),
        egui::StrokeKind::Outside,
    );
    let font = egui::FontId::proportional(12.0);
    let text = |pos: Pos2, s: String, align| {
        painter.text(pos, align, s, font.clone(), Color32::WHITE);
    };
    for k in 0..=4 {
        let t = k as f64 / 4.0;
        let y = bar.max.y - t as f32 * bar.height();
        text(
            Pos2::new(bar.max.x + 6.0, y),
            format!("{:.3}", lo + t * (hi - lo)),
            egui::Align2::LEFT_CENTER,
        );
    }
    text(
        Pos2::new(bar.min.x, bar.min.y - 16.0),
        format!(
            "{}{} ({}){}",
            if mesh.difference { "Δ " } else { "" },
            q.label(),
            q.unit(),
            match (options.fixed_range, shared) {
                (true, _) => ", fixed",
                (false, true) => ", shared",
                (false, false) => "",
            }
        ),
        egui::Align2::LEFT_CENTER,
    );
    text(
        Pos2::new(bar.min.x, bar.max.y + 16.0),
        format!("min {min:.3}  max {max:.3}"),
        egui::Align2::LEFT_CENTER,
    );
}

fn rgb(c: [f32; 3]) -> Color32 {
    Color32::from_rgb(
        (c[0] * 255.0).round() as u8,
        (c[1] * 255.0).round() as u8,
        (c[2] * 255.0).round() as u8,
    )
}
