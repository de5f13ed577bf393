//! How bodies are joined and held: the interface overrides between pairs of bodies and the
//! boundary conditions on box faces and physical surfaces (METHOD §5 laws), checked against the
//! bodies by name.

use std::collections::HashMap;

use crate::error::{LopinError, Result};
use crate::scene::spec::{face_of, InterfaceKind, SceneSpec};

use super::boundary_laws::boundary_dofs;
use super::ranges::check_friction;

/// The interface overrides: bodies known and distinct, one override per pair, the contact
/// fields only on contacts and in range.
pub(super) fn check_interfaces(
    spec: &SceneSpec,
    source: &str,
    body_index: &HashMap<&str, usize>,
) -> Result<()> {
    let err = |field: String, reason: String| Err(LopinError::scene(source, field, reason));
    let mut pairs: HashMap<(usize, usize), usize> = HashMap::with_capacity(spec.interfaces.len());
    for (i, it) in spec.interfaces.iter().enumerate() {
        for (j, name) in it.bodies.iter().enumerate() {
            if !body_index.contains_key(name.as_str()) {
                return err(
                    format!("interface[{i}].bodies[{j}]"),
                    format!("no body named `{name}`"),
                );
            }
        }
        if it.bodies[0] == it.bodies[1] {
            return err(
                format!("interface[{i}].bodies"),
                "the two bodies must differ".into(),
            );
        }
        if let Some(first) = pairs.insert(pair_key(body_index, &it.bodies), i) {
            return err(
                format!("interface[{i}].bodies"),
                format!(
                    "bodies `{}` and `{}` already have an override (interface[{first}])",
                    it.bodies[0], it.bodies[1]
                ),
            );
        }
        let contact = it.kind == InterfaceKind::Contact;
        for (field, value) in [
            ("friction", it.friction),
            ("gap", it.gap),
            ("search", it.search),
        ] {
            if let Some(v) = value {
                if !contact {
                    return err(
                        format!("interface[{i}].{field}"),
                        format!("only a contact interface takes `{field}`"),
                    );
                }
                if field == "gap" && !v.is_finite() {
                    return err(
                        format!("interface[{i}].gap"),
                        format!(
                            "must be a number (negative: an interference the preload closes), got {v}"
                        ),
                    );
                }
                if field != "gap" && !(v.is_finite() && v >= 0.0) {
                    return err(
                        format!("interface[{i}].{field}"),
                        format!("must be a non-negative number, got {v}"),
                    );
                }
                if field == "friction" {
                    check_friction(v).map_err(|r| {
                        LopinError::scene(source, format!("interface[{i}].friction"), r)
                    })?;
                }
            }
        }
    }
    Ok(())
}

/// The boundaries: one entry per face or surface, on a known body, a box face on a box body
/// and a physical surface on a mesh body, with laws that can be built.
pub(super) fn check_boundaries(
    spec: &SceneSpec,
    source: &str,
    body_index: &HashMap<&str, usize>,
) -> Result<()> {
    let err = |field: String, reason: String| Err(LopinError::scene(source, field, reason));
    let mut boundary_places: HashMap<(&str, &str, Option<&str>), usize> = HashMap::new();
    for (i, bc) in spec.boundaries.iter().enumerate() {
        let place = (bc.body.as_str(), bc.face.as_str(), bc.surface.as_deref());
        if let Some(first) = boundary_places.insert(place, i) {
            return err(
                format!("boundary[{i}]"),
                format!(
                    "repeats boundary[{first}]: both act on {} of `{}`; give each face or \
                     surface one [[boundary]] entry (its x, y and z components together)",
                    bc.surface
                        .as_ref()
                        .map_or_else(|| format!("face {}", bc.face), |s| format!("surface `{s}`")),
                    bc.body
                ),
            );
        }
        let Some(&body) = body_index.get(bc.body.as_str()) else {
            return err(
                format!("boundary[{i}].body"),
                format!("no body named `{}`", bc.body),
            );
        };
        if body >= spec.bodies.len() {
            // a mesh body: a physical surface, not a box face
            if bc.surface.is_none() || !bc.face.is_empty() {
                return err(
                    format!("boundary[{i}].surface"),
                    format!(
                        "`{}` is a mesh body: name a physical surface of its file with `surface = \"...\"` (not a box `face`)",
                        bc.body
                    ),
                );
            }
            boundary_dofs(bc).map_err(|(field, reason)| {
                LopinError::scene(source, format!("boundary[{i}].{field}"), reason)
            })?;
            continue;
        }
        if bc.surface.is_some() {
            return err(
                format!("boundary[{i}].surface"),
                format!(
                    "`{}` is a box body: its boundaries name a `face` (x-, x+, y-, y+, z-, z+); \
                     physical surfaces belong to [[mesh_body]] bodies",
                    bc.body
                ),
            );
        }
        if face_of(&bc.face).is_none() {
            return err(
                format!("boundary[{i}].face"),
                format!("expected one of x-, x+, y-, y+, z-, z+, got `{}`", bc.face),
            );
        }
        boundary_dofs(bc).map_err(|(field, reason)| {
            LopinError::scene(source, format!("boundary[{i}].{field}"), reason)
        })?;
    }
    Ok(())
}

/// The unordered pair of two (existing) body names as ordered body indices.
pub(crate) fn pair_key(body_index: &HashMap<&str, usize>, bodies: &[String; 2]) -> (usize, usize) {
    let a = body_index
        .get(bodies[0].as_str())
        .copied()
        .unwrap_or_default();
    let b = body_index
        .get(bodies[1].as_str())
        .copied()
        .unwrap_or_default();
    (a.min(b), a.max(b))
}
