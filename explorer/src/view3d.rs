//! The 3D view widget: mouse orbit (drag), pan (right or middle drag, or shift-drag), zoom
//! (scroll), reset (double-click), picking a probe node (click), the wgpu paint callback, the
//! colour legend with quantity, unit, range and min/max (diverging for a difference field), and
//! a note over the view (what is shown while a re-solve refines it, what is compared).

use crate::colormap;
use crate::geometry::SceneGeometry;
use crate::layout::Layout;
use crate::mesh_build;
use crate::render::{SceneCallback, Uniforms};
use eframe::egui_wgpu;
use egui::{Color32, Pos2, Rect, Sense, Stroke, Vec2};

const BACKGROUND: [f32; 3] = [0.105, 0.11, 0.125];

/// Draws the 3D view of `layout`'s mesh in the remaining space (with the wgpu renderer when
/// `gpu`), with `note` in its top-left corner, and moves its camera. Returns the node a click
/// picked (substructure, node).
pub fn show(
    ui: &mut egui::Ui,
    layout: &mut Layout,
    geometry: &SceneGeometry,
    gpu: bool,
    note: Option<&str>,
) -> Option<(usize, usize)> {
    let rect = ui.available_rect_before_wrap();
    let response = ui.allocate_rect(rect, Sense::click_and_drag());
    layout.set_view_rect(rect);
    response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Canvas, true, "3D view"));
    let aspect = rect.width() / rect.height().max(1.0);
    // camera input
    let pan = response.dragged_by(egui::PointerButton::Secondary)
        || response.dragged_by(egui::PointerButton::Middle)
        || (response.dragged_by(egui::PointerButton::Primary) && ui.input(|i| i.modifiers.shift));
    let d = response.drag_delta();
    if pan {
        layout.camera.pan(d.x, d.y, rect.height());
    } else if response.dragged_by(egui::PointerButton::Primary) {
        layout.camera.orbit(d.x, d.y);
    }
    if response.hovered() {
        let scroll = ui.input(|i| i.smooth_scroll_delta.y);
        if scroll != 0.0 {
            layout.camera.zoom((scroll * 0.002).exp());
        }
    }
    let mut picked = None;
    if response.double_clicked() {
        layout.reset_camera();
    } else if response.clicked() {
        if let Some(p) = response.interact_pointer_pos() {
            let ndc_x = 2.0 * (p.x - rect.left()) / rect.width() - 1.0;
            let ndc_y = 1.0 - 2.0 * (p.y - rect.top()) / rect.height();
            let (o, dir) = layout.camera.ray(ndc_x, ndc_y, aspect);
            picked = mesh_build::pick(layout.mesh(), layout.section(geometry), o, dir, geometry);
        }
    }
    let ppp = ui.ctx().pixels_per_point();
    if gpu {
        let view_proj = layout.camera.view_proj(aspect);
        let light = (layout.camera.eye() - layout.camera.target).normalize_or_zero()
            + glam::Vec3::new(0.3, 0.2, 0.6);
        let cb = SceneCallback {
            mesh: layout.mesh().clone(),
            version: layout.mesh_version(),
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
    } else {
        ui.painter().text(
            rect.center(),
            egui::Align2::CENTER_CENTER,
            "The 3D view needs the wgpu renderer.",
            egui::FontId::proportional(16.0),
            Color32::LIGHT_GRAY,
        );
    }
    legend(layout, ui, rect);
    if let Some(note) = note {
        let painter = ui.painter_at(rect);
        let font = egui::FontId::proportional(14.0);
        let galley = painter.layout_no_wrap(note.to_string(), font, Color32::WHITE);
        let at = rect.left_top() + Vec2::new(12.0, 10.0);
        painter.rect_filled(
            Rect::from_min_size(at, galley.size()).expand(5.0),
            4.0,
            Color32::from_black_alpha(170),
        );
        painter.galley(at, galley, Color32::WHITE);
    }
    if layout.mesh().vertices.is_empty() {
        ui.painter().text(
            rect.center(),
            egui::Align2::CENTER_CENTER,
            "solving…",
            egui::FontId::proportional(18.0),
            Color32::LIGHT_GRAY,
        );
    }
    picked
}

/// Colour bar in the lower-left corner of the view.
fn legend(layout: &Layout, ui: &egui::Ui, view: Rect) {
    let q = layout.view.quantity;
    let (lo, hi) = layout.mesh().range;
    let (min, max) = layout.mesh().extent;
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
        let c = if layout.mesh().difference {
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
            if layout.mesh().difference { "Δ " } else { "" },
            q.label(),
            q.unit(),
            if layout.view.fixed_range {
                ", fixed"
            } else {
                ""
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
