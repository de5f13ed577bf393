//! Zones: interfaces grouped under a name in the scene file (`[[zone]]`), so that each zone's
//! friction coefficient, initial gap, prescribed velocity amplitude and preload is a parameter of
//! its own (the laws of METHOD §5, the multiresolution restarts of METHOD §8).
//!
//! A zone selects the contact interfaces between the body pairs it lists (`bodies`; none: every
//! pair) whose centre lies in its box (`min`, `max`; none: anywhere) and that lie on one of the
//! physical surfaces of Gmsh meshes it names (`surfaces`; none: anywhere; the contacts are split by
//! surface, [`crate::interfaces::surface_groups`]), and, for `v0` and `preload`, the boundary
//! interfaces with a non-zero prescribed velocity or a preload of the bodies it names (none: every
//! body) whose centre lies in the box and whose surface it names. A zone that selects nothing,
//! names an unknown body or a surface no mesh file defines, or repeats a name is an error naming
//! the field.

use crate::error::{LopinError, Result};
use crate::interfaces::interface::{DofLaw, Interface, Law};
use crate::substructure::Substructure;

/// The interfaces of one zone.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Zone {
    /// Name in the scene file (how `--param f@NAME` refers to it).
    pub name: String,
    /// Contact interfaces (friction, gap).
    pub contacts: Vec<usize>,
    /// Boundary interfaces with a prescribed velocity component (v0) or a preload.
    pub boundaries: Vec<usize>,
}

impl Zone {
    /// Whether interface `i` belongs to the zone.
    pub fn holds(&self, i: usize) -> bool {
        self.contacts.binary_search(&i).is_ok() || self.boundaries.binary_search(&i).is_ok()
    }
}

/// The zone block of a scene file.
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ZoneSpec {
    /// Name, unique among the zones: letters, digits, `-` and `_`.
    pub name: String,
    /// Body pairs whose contact interfaces it holds (empty: every pair).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub bodies: Vec<[String; 2]>,
    /// Lower corner of the box holding the interfaces' centres (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min: Option<[f64; 3]>,
    /// Upper corner of that box (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max: Option<[f64; 3]>,
    /// Physical surfaces of the mesh bodies' Gmsh files whose contact interfaces (and
    /// prescribed velocities) it holds (empty: any).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub surfaces: Vec<String>,
}

/// The physical surfaces the zones name, each once in order of first mention, with the field
/// that first names it (`zone[i].surfaces[j]`).
pub fn surface_names(specs: &[ZoneSpec]) -> Vec<(&str, String)> {
    let mut out: Vec<(&str, String)> = Vec::new();
    for (z, spec) in specs.iter().enumerate() {
        for (j, name) in spec.surfaces.iter().enumerate() {
            if out.iter().all(|o| o.0 != name) {
                out.push((name, format!("zone[{z}].surfaces[{j}]")));
            }
        }
    }
    out
}

/// The centre of an interface: the mean of its first side's nodes.
fn centre(iface: &Interface, subs: &[Substructure]) -> [f64; 3] {
    let side = &iface.sides[0];
    let nodes = &subs[side.sub].mesh.nodes;
    let mut c = [0.0; 3];
    for &n in &side.nodes {
        for q in 0..3 {
            c[q] += nodes[n][q];
        }
    }
    let count = side.nodes.len().max(1) as f64;
    c.map(|x| x / count)
}

/// The zones of a scene resolved on its interfaces (`surface_of`: the physical surface each
/// interface lies on, if any); errors name `source` and `zone[i].FIELD`.
pub fn resolve(
    specs: &[ZoneSpec],
    subs: &[Substructure],
    interfaces: &[Interface],
    surface_of: &[Option<String>],
    source: &str,
) -> Result<Vec<Zone>> {
    let bodies: std::collections::HashSet<&str> = subs.iter().map(|s| s.body.as_str()).collect();
    let mut zones: Vec<Zone> = Vec::with_capacity(specs.len());
    for (z, spec) in specs.iter().enumerate() {
        check_name(spec, z, &zones, source)?;
        let bounds = check_bodies_and_box(spec, z, &bodies, source)?;
        let zone = select(spec, bounds, subs, interfaces, surface_of);
        if zone.contacts.is_empty() && zone.boundaries.is_empty() {
            return Err(zone_error(
                source,
                z,
                if !spec.surfaces.is_empty() {
                    "surfaces"
                } else if spec.min.is_some() || spec.max.is_some() {
                    "min"
                } else {
                    "bodies"
                },
                format!(
                    "zone `{}` holds no contact interface and no prescribed velocity",
                    spec.name
                ),
            ));
        }
        zones.push(zone);
    }
    Ok(zones)
}

/// The error for field `zone[z].f` of `source`.
fn zone_error(source: &str, z: usize, f: &str, why: String) -> LopinError {
    LopinError::scene(source, format!("zone[{z}].{f}"), why)
}

/// Checks the name of zone `z`: not empty, only letters, digits, `-` and `_`, and not that of
/// an earlier zone (`zones`).
fn check_name(spec: &ZoneSpec, z: usize, zones: &[Zone], source: &str) -> Result<()> {
    let named = !spec.name.is_empty()
        && spec
            .name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_');
    if !named {
        return Err(zone_error(
            source,
            z,
            "name",
            format!(
                "`{}` is not a zone name (letters, digits, `-` and `_`)",
                spec.name
            ),
        ));
    }
    if zones.iter().any(|o| o.name == spec.name) {
        return Err(zone_error(
            source,
            z,
            "name",
            format!("zone `{}` is defined twice", spec.name),
        ));
    }
    Ok(())
}

/// Checks that zone `z` names only existing `bodies` and that its box has each lower bound
/// below the upper one; returns the box's corners (unbounded where not given).
fn check_bodies_and_box(
    spec: &ZoneSpec,
    z: usize,
    bodies: &std::collections::HashSet<&str>,
    source: &str,
) -> Result<([f64; 3], [f64; 3])> {
    for (p, pair) in spec.bodies.iter().enumerate() {
        for b in pair {
            if !bodies.contains(b.as_str()) {
                return Err(zone_error(
                    source,
                    z,
                    &format!("bodies[{p}]"),
                    format!("no body is named `{b}`"),
                ));
            }
        }
    }
    let (lo, hi) = (
        spec.min.unwrap_or([f64::NEG_INFINITY; 3]),
        spec.max.unwrap_or([f64::INFINITY; 3]),
    );
    if let Some(q) = (0..3).find(|&q| lo[q].partial_cmp(&hi[q]).is_none_or(|o| o.is_gt())) {
        return Err(zone_error(
            source,
            z,
            "min",
            format!("min[{q}] = {} is not below max[{q}] = {}", lo[q], hi[q]),
        ));
    }
    Ok((lo, hi))
}

/// The interfaces zone `spec` holds: the contacts between the body pairs it lists, and the
/// boundary interfaces with a non-zero prescribed velocity amplitude of the bodies it names,
/// each with its centre in the box `(lo, hi)` and on one of the surfaces it names (`surface_of`).
fn select(
    spec: &ZoneSpec,
    (lo, hi): ([f64; 3], [f64; 3]),
    subs: &[Substructure],
    interfaces: &[Interface],
    surface_of: &[Option<String>],
) -> Zone {
    let inside = |iface: &Interface| {
        let c = centre(iface, subs);
        (0..3).all(|q| lo[q] <= c[q] && c[q] <= hi[q])
    };
    let pair_listed = |a: &str, b: &str| {
        spec.bodies.is_empty()
            || spec
                .bodies
                .iter()
                .any(|[x, y]| (x == a && y == b) || (x == b && y == a))
    };
    let body_named =
        |a: &str| spec.bodies.is_empty() || spec.bodies.iter().any(|[x, y]| x == a || y == a);
    let on_surface = |i: usize| {
        spec.surfaces.is_empty()
            || surface_of
                .get(i)
                .and_then(Option::as_deref)
                .is_some_and(|s| spec.surfaces.iter().any(|n| n == s))
    };
    let mut zone = Zone {
        name: spec.name.clone(),
        contacts: Vec::new(),
        boundaries: Vec::new(),
    };
    for (i, iface) in interfaces.iter().enumerate() {
        let body = |s: usize| subs[iface.sides[s].sub].body.as_str();
        match &iface.law {
            Law::Contact(_) if pair_listed(body(0), body(1)) && inside(iface) && on_surface(i) => {
                zone.contacts.push(i);
            }
            Law::Boundary(dofs)
                if dofs.iter().any(|d| {
                    d.preload || matches!(&d.law, DofLaw::Velocity(f) if f.amplitude != 0.0)
                }) && body_named(body(0))
                    && inside(iface)
                    && on_surface(i) =>
            {
                zone.boundaries.push(i);
            }
            _ => {}
        }
    }
    zone
}
