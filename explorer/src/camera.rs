//! The orbit camera of the 3D view: yaw/pitch/distance around a target (z up), pan, zoom,
//! reset, and the view-projection matrix in wgpu's clip space (depth 0..1), whose field of view
//! widens for viewports narrower than [`MIN_ASPECT`] (the halves of the side-by-side view). Also
//! the picking ray of a screen point.

use glam::{Mat4, Vec3, Vec4};

/// A viewport narrower than this (width / height) widens its vertical field of view so that it
/// shows as much across as a viewport of this shape: the scene stays framed in the tall halves
/// of the side-by-side view, while the usual views (wider than this) are unchanged.
pub const MIN_ASPECT: f32 = 0.8;

/// An orbit camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Point looked at.
    pub target: Vec3,
    /// Angle around z, radians.
    pub yaw: f32,
    /// Angle above the xy plane, radians.
    pub pitch: f32,
    /// Distance from the target.
    pub distance: f32,
    /// Vertical field of view, radians.
    pub fov: f32,
}

impl Camera {
    /// A view of the box [lo, hi] from the front-right, above.
    pub fn framing(lo: Vec3, hi: Vec3) -> Camera {
        let radius = 0.5 * (hi - lo).length().max(1e-9);
        let fov = 35f32.to_radians();
        Camera {
            target: 0.5 * (lo + hi),
            yaw: -55f32.to_radians(),
            pitch: 25f32.to_radians(),
            distance: 1.15 * radius / (0.5 * fov).sin(),
            fov,
        }
    }

    /// Eye position.
    pub fn eye(&self) -> Vec3 {
        let (cp, sp) = (self.pitch.cos(), self.pitch.sin());
        self.target + self.distance * Vec3::new(cp * self.yaw.cos(), cp * self.yaw.sin(), sp)
    }

    /// Rotates by a mouse drag (pixels).
    pub fn orbit(&mut self, dx: f32, dy: f32) {
        self.yaw -= dx * 0.008;
        self.pitch = (self.pitch + dy * 0.008).clamp(-1.55, 1.55);
    }

    /// Moves the target in the view plane by a drag of (dx, dy) pixels in a view `width` ×
    /// `height` large.
    pub fn pan(&mut self, dx: f32, dy: f32, width: f32, height: f32) {
        let (right, up) = self.axes();
        let fov = self.vertical_fov(width / height.max(1.0));
        let per_px = 2.0 * self.distance * (0.5 * fov).tan() / height.max(1.0);
        self.target += (-dx * right + dy * up) * per_px;
    }

    /// The vertical field of view of a viewport of this aspect ratio (width / height): the
    /// camera's, widened below [`MIN_ASPECT`].
    pub fn vertical_fov(&self, aspect: f32) -> f32 {
        if aspect >= MIN_ASPECT || aspect <= 0.0 {
            return self.fov;
        }
        2.0 * ((0.5 * self.fov).tan() * MIN_ASPECT / aspect).atan()
    }

    /// Zooms by a factor (> 1 moves closer).
    pub fn zoom(&mut self, factor: f32) {
        self.distance = (self.distance / factor.max(1e-3)).max(1e-9);
    }

    fn axes(&self) -> (Vec3, Vec3) {
        let forward = (self.target - self.eye()).normalize();
        let right = forward.cross(Vec3::Z).normalize_or(Vec3::X);
        (right, right.cross(forward))
    }

    /// View-projection matrix for an aspect ratio (width / height).
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        let near = 0.01 * self.distance;
        let far = 100.0 * self.distance;
        let fov = self.vertical_fov(aspect);
        perspective(fov, aspect, near, far) * look_at(self.eye(), self.target, Vec3::Z)
    }

    /// The ray (origin, unit direction) through a point of the view, in normalized device
    /// coordinates (x, y in [−1, 1], y up).
    pub fn ray(&self, ndc_x: f32, ndc_y: f32, aspect: f32) -> (Vec3, Vec3) {
        let inv = self.view_proj(aspect).inverse();
        let a = inv * Vec4::new(ndc_x, ndc_y, 0.0, 1.0);
        let b = inv * Vec4::new(ndc_x, ndc_y, 1.0, 1.0);
        let (a, b) = (a.truncate() / a.w, b.truncate() / b.w);
        (a, (b - a).normalize())
    }
}

/// Right-handed perspective with depth in [0, 1] (wgpu, Direct3D convention).
fn perspective(fov: f32, aspect: f32, near: f32, far: f32) -> Mat4 {
    let f = 1.0 / (0.5 * fov).tan();
    let r = far / (near - far);
    Mat4::from_cols(
        Vec4::new(f / aspect, 0.0, 0.0, 0.0),
        Vec4::new(0.0, f, 0.0, 0.0),
        Vec4::new(0.0, 0.0, r, -1.0),
        Vec4::new(0.0, 0.0, r * near, 0.0),
    )
}

/// Right-handed view matrix.
fn look_at(eye: Vec3, center: Vec3, up: Vec3) -> Mat4 {
    let f = (center - eye).normalize();
    let s = f.cross(up).normalize_or(Vec3::X);
    let u = s.cross(f);
    Mat4::from_cols(
        Vec4::new(s.x, u.x, -f.x, 0.0),
        Vec4::new(s.y, u.y, -f.y, 0.0),
        Vec4::new(s.z, u.z, -f.z, 0.0),
        Vec4::new(-s.dot(eye), -u.dot(eye), f.dot(eye), 1.0),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn target_projects_to_the_centre_and_depth_stays_in_zero_one() {
        let c = Camera::framing(Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0));
        let m = c.view_proj(1.5);
        let p = m * c.target.extend(1.0);
        let ndc = p.truncate() / p.w;
        assert!(ndc.x.abs() < 1e-5 && ndc.y.abs() < 1e-5, "{ndc}");
        assert!(ndc.z > 0.0 && ndc.z < 1.0, "{ndc}");
        // a point behind the target is deeper
        let behind = c.target + (c.target - c.eye()) * 0.5;
        let q = m * behind.extend(1.0);
        assert!(q.z / q.w > ndc.z);
    }

    #[test]
    fn a_narrow_viewport_shows_as_much_across_as_one_of_the_minimum_aspect() {
        let c = Camera::framing(Vec3::ZERO, Vec3::ONE);
        assert_eq!(c.vertical_fov(1.5), c.fov);
        assert_eq!(c.vertical_fov(MIN_ASPECT), c.fov);
        // the horizontal half-width at unit depth: aspect × tan(vertical fov / 2)
        let across = |aspect: f32| aspect * (0.5 * c.vertical_fov(aspect)).tan();
        assert!((across(0.4) - across(MIN_ASPECT)).abs() < 1e-6);
        assert!(c.vertical_fov(0.4) > c.fov);
        // the picking ray goes through the same point the projection puts at the edge
        let m = c.view_proj(0.4);
        let (o, d) = c.ray(1.0, 0.0, 0.4);
        let p = m * (o + d * c.distance).extend(1.0);
        assert!((p.x / p.w - 1.0).abs() < 1e-4, "{p}");
    }

    #[test]
    fn the_centre_ray_passes_through_the_target() {
        let c = Camera::framing(Vec3::ZERO, Vec3::ONE);
        let (o, d) = c.ray(0.0, 0.0, 1.0);
        let to_target = c.target - o;
        let miss = (to_target - d * to_target.dot(d)).length();
        assert!(miss < 1e-4 * c.distance, "{miss}");
    }
}
