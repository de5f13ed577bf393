//! Turns the fields of the displayed step into the triangles the GPU draws: each
//! substructure's boundary faces (deformed, exploded, coloured through the colormap) and the
//! faces cut by the section plane; or, to compare two configurations, the difference of their
//! nodal values on a symmetric diverging colour range, or the colour range both share when they
//! are drawn side by side. Rebuilt only when an input changes, never for a camera move.

use crate::colormap::{self, Range};
use crate::fields::StepFields;
use crate::geometry::SceneGeometry;
use crate::quantity::Quantity;
use crate::section::Section;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use lopin_core::post::ContactHistory;

/// One vertex of the drawn mesh.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct Vertex {
    /// Position (deformed, exploded), m.
    pub position: [f32; 3],
    /// Flat normal of its face.
    pub normal: [f32; 3],
    /// sRGB colour.
    pub color: [f32; 3],
    /// Signed distance from the section plane (> 0 is cut away; −1 without a section).
    pub clip: f32,
    /// Substructure index (a tiny depth offset per body avoids z-fighting of touching faces).
    pub body: f32,
}

/// A surface triangle kept for picking: where it is drawn and which nodes it joins.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PickTriangle {
    /// Substructure.
    pub sub: usize,
    /// Its nodes.
    pub nodes: [usize; 3],
    /// Drawn corner positions.
    pub corners: [Vec3; 3],
}

/// Everything the view needs to draw and pick.
#[derive(Debug, Clone, Default)]
pub struct MeshData {
    /// Triangle list.
    pub vertices: Vec<Vertex>,
    /// Surface triangles for picking (cut faces excluded).
    pub picks: Vec<PickTriangle>,
    /// Colour range used, display units.
    pub range: (f64, f64),
    /// Min and max of the displayed values, display units.
    pub extent: (f64, f64),
    /// Whether it shows a difference of two configurations (diverging colours).
    pub difference: bool,
}

/// What the drawn mesh depends on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshInputs {
    /// Coloured quantity.
    pub quantity: Quantity,
    /// Colour range.
    pub range: Range,
    /// Deformation scale (0: undeformed).
    pub deform: f32,
    /// Exploded-view factor (0: assembled).
    pub explode: f32,
    /// Section plane, if any.
    pub section: Option<Section>,
}

/// Nodal values of quantity `q` in display units, per substructure (None: no value there, as
/// off the contact interfaces for an interface quantity). `contact`: contact histories of the
/// same solution as `fields`.
pub fn nodal_values(
    geo: &SceneGeometry,
    fields: &StepFields,
    contact: Option<&[ContactHistory]>,
    q: Quantity,
) -> Vec<Vec<Option<f64>>> {
    let step = fields.step;
    geo.subs
        .iter()
        .zip(&fields.subs)
        .map(|(g, f)| {
            (0..g.nodes.len())
                .map(|n| match q {
                    Quantity::VonMises => Some(f.von_mises[n] * q.scale()),
                    Quantity::Velocity => {
                        let v = &f.v[3 * n..3 * n + 3];
                        Some((v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt() * q.scale())
                    }
                    Quantity::Pressure | Quantity::Slip | Quantity::Gap => {
                        let cn = g.contact[n]?;
                        let h = contact?.get(cn.contact)?;
                        let table = match q {
                            Quantity::Pressure => &h.pressure,
                            Quantity::Slip => &h.slip,
                            _ => &h.gap,
                        };
                        Some(table.get(step)?.get(cn.node)? * q.scale())
                    }
                })
                .collect()
        })
        .collect()
}

/// The node-by-node difference `a − b` of two sets of nodal values (None where either has none).
pub fn difference(a: &[Vec<Option<f64>>], b: &[Vec<Option<f64>>]) -> Vec<Vec<Option<f64>>> {
    a.iter()
        .zip(b)
        .map(|(x, y)| x.iter().zip(y).map(|(p, q)| Some((*p)? - (*q)?)).collect())
        .collect()
}

/// A configuration as the mesh is built from it: its fields at one step and its contact
/// histories.
pub type Configuration<'a> = (&'a StepFields, Option<&'a [ContactHistory]>);

/// A configuration to subtract from the drawn one (its fields at the same step).
pub type Minus<'a> = Configuration<'a>;

/// The colour range two configurations drawn side by side share, display units: the fixed
/// range, or the min and max of quantity `q` over both (each a configuration's fields at the
/// same step and its contact histories), so equal colours mean equal values.
pub fn shared_range(
    geo: &SceneGeometry,
    a: Configuration<'_>,
    b: Configuration<'_>,
    range: Range,
    q: Quantity,
) -> (f64, f64) {
    let a = nodal_values(geo, a.0, a.1, q);
    let b = nodal_values(geo, b.0, b.1, q);
    let all = a.iter().chain(&b).flatten().flatten().copied();
    colormap::resolve(range, all)
}

/// Builds the mesh. `contact`: contact histories of the same solution (for interface
/// quantities); `minus`: a configuration whose values are subtracted (the difference field,
/// coloured on a symmetric range).
pub fn build(
    geo: &SceneGeometry,
    fields: &StepFields,
    contact: Option<&[ContactHistory]>,
    inputs: &MeshInputs,
    minus: Option<Minus<'_>>,
) -> MeshData {
    let q = inputs.quantity;
    let mut values = nodal_values(geo, fields, contact, q);
    if let Some((f, c)) = minus {
        values = difference(&values, &nodal_values(geo, f, c, q));
    }
    let extent = colormap::resolve(Range::Auto, values.iter().flatten().flatten().copied());
    let all = values.iter().flatten().flatten().copied();
    let diverging = minus.is_some();
    let (lo, hi) = if diverging {
        colormap::resolve_symmetric(inputs.range, all)
    } else {
        colormap::resolve(inputs.range, all)
    };
    let color = |v: Option<f64>| {
        v.map_or(colormap::NEUTRAL, |v| {
            if diverging {
                colormap::diverging(v, lo, hi)
            } else {
                colormap::color(v, lo, hi)
            }
        })
    };
    let mut out = MeshData {
        range: (lo, hi),
        extent,
        difference: diverging,
        ..MeshData::default()
    };
    for (i, (g, f)) in geo.subs.iter().zip(&fields.subs).enumerate() {
        let offset = geo.explode_offset(i, inputs.explode);
        let drawn: Vec<Vec3> = g
            .nodes
            .iter()
            .enumerate()
            .map(|(n, &x)| {
                let u = Vec3::new(
                    f.u[3 * n] as f32,
                    f.u[3 * n + 1] as f32,
                    f.u[3 * n + 2] as f32,
                );
                x + inputs.deform * u + offset
            })
            .collect();
        let clip = |n: usize| inputs.section.map_or(-1.0, |s| s.side(g.nodes[n]));
        let body = i as f32;
        // assembled, a face between two substructures is hidden by both: left out (a section
        // draws its own cut faces)
        let assembled = inputs.explode == 0.0;
        for (face, _) in g
            .faces
            .iter()
            .zip(&g.enclosed)
            .filter(|(_, &e)| !(assembled && e))
        {
            // interface quantities colour only the faces lying wholly on a contact interface
            let on_face = |n: usize| {
                if q.on_interfaces() && face.iter().any(|&m| values[i][m].is_none()) {
                    None
                } else {
                    values[i][n]
                }
            };
            // a triangle is stored as a quadrangle with its last node repeated
            let tris = [[face[0], face[1], face[2]], [face[0], face[2], face[3]]];
            let count = if face[2] == face[3] { 1 } else { 2 };
            for tri in tris.into_iter().take(count) {
                let p = tri.map(|n| drawn[n]);
                let normal = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
                for &n in &tri {
                    out.vertices.push(Vertex {
                        position: drawn[n].to_array(),
                        normal: normal.to_array(),
                        color: color(on_face(n)),
                        clip: clip(n),
                        body,
                    });
                }
                out.picks.push(PickTriangle {
                    sub: i,
                    nodes: tri,
                    corners: p,
                });
            }
        }
        if let Some(s) = inputs.section {
            let mut normal = Vec3::ZERO;
            normal[s.axis] = 1.0;
            for hex in &g.elements {
                let Some(poly) = s.cut(&g.nodes, hex) else {
                    continue;
                };
                let corner = |k: usize| {
                    let c = poly[k];
                    let p = drawn[c.a].lerp(drawn[c.b], c.t);
                    let v = match (values[i][c.a], values[i][c.b]) {
                        (Some(a), Some(b)) if !q.on_interfaces() => {
                            Some(a + (b - a) * f64::from(c.t))
                        }
                        _ => None,
                    };
                    Vertex {
                        position: p.to_array(),
                        normal: normal.to_array(),
                        color: color(v),
                        clip: -1.0,
                        body,
                    }
                };
                for k in 1..poly.len() - 1 {
                    out.vertices.push(corner(0));
                    out.vertices.push(corner(k));
                    out.vertices.push(corner(k + 1));
                }
            }
        }
    }
    out
}

/// The node nearest to where a ray first hits the drawn surface (cut-away parts ignored).
pub fn pick(
    mesh: &MeshData,
    section: Option<Section>,
    origin: Vec3,
    dir: Vec3,
    geo: &SceneGeometry,
) -> Option<(usize, usize)> {
    let mut best: Option<(f32, usize, usize)> = None;
    for t in &mesh.picks {
        if let Some(s) = section {
            if t.nodes
                .iter()
                .all(|&n| s.side(geo.subs[t.sub].nodes[n]) > 0.0)
            {
                continue;
            }
        }
        let Some(d) = ray_triangle(origin, dir, t.corners) else {
            continue;
        };
        if best.is_none_or(|b| d < b.0) {
            let hit = origin + d * dir;
            let k = (0..3)
                .min_by(|&a, &b| {
                    hit.distance(t.corners[a])
                        .total_cmp(&hit.distance(t.corners[b]))
                })
                .unwrap_or(0);
            best = Some((d, t.sub, t.nodes[k]));
        }
    }
    best.map(|(_, s, n)| (s, n))
}

/// Möller–Trumbore: distance along the ray to the triangle, if it is hit in front.
fn ray_triangle(o: Vec3, d: Vec3, [a, b, c]: [Vec3; 3]) -> Option<f32> {
    let (e1, e2) = (b - a, c - a);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-20 {
        return None;
    }
    let inv = 1.0 / det;
    let s = o - a;
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = d.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(q) * inv;
    (t > 0.0).then_some(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ray_hits_a_triangle_at_the_right_distance() {
        let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let t = ray_triangle(Vec3::new(0.2, 0.2, 5.0), -Vec3::Z, tri);
        assert!((t.expect("hit") - 5.0).abs() < 1e-6);
        assert!(ray_triangle(Vec3::new(0.9, 0.9, 5.0), -Vec3::Z, tri).is_none());
        assert!(ray_triangle(Vec3::new(0.2, 0.2, 5.0), Vec3::Z, tri).is_none());
    }
}
