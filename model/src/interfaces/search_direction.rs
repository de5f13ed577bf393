//! The shape of the search directions E± (METHOD §3): the scalar k of the method (every trace
//! dof gets k, `isotropic`) or a direction matched to the waves (`wave`), whose normal part is
//! the P-wave impedance ρc_p and whose tangential parts are the S-wave impedance ρc_s of the
//! materials across the interface, both scaled by k / k0 (k0 = mean √(ρE), METHOD §10) so that
//! the k setting still scales the whole direction.
//!
//! A direction is stored as a dimensionless factor per trace dof (k_j = k · s_j), the same on
//! both sides of an interface, so it is diagonal in global axes: the wave direction is applied
//! to interfaces whose normal is a coordinate axis (every box face); an interface with another
//! normal keeps the scalar k. Every formula of METHOD §4–§9 that reads k then reads k_j: the
//! operator S (Bᵀ A K B), the right-hand side Bᵀ A (F̂ + K Ŵ), the forces F = F̂ + K (Ŵ − W), the
//! closed forms of the local stage (perfect, prescribed, contact with k_n and k_t) and the η
//! norm.

use crate::elements::material::Material;
use crate::interfaces::interface::{Interface, Law};
use crate::problem::Problem;

/// The shape of the search direction.
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize, Hash,
)]
#[serde(rename_all = "lowercase")]
pub enum Directions {
    /// k on every dof (METHOD §3 as written).
    #[default]
    Isotropic,
    /// ρc_p · k/k0 along the interface normal, ρc_s · k/k0 along it.
    Wave,
}

impl Directions {
    /// The name used in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Isotropic => "isotropic",
            Self::Wave => "wave",
        }
    }

    /// Parses a name; the error lists the accepted ones.
    pub fn parse(name: &str) -> Result<Self, String> {
        match name {
            "isotropic" => Ok(Self::Isotropic),
            "wave" => Ok(Self::Wave),
            _ => Err(format!(
                "unknown search direction '{name}' (expected isotropic or wave)"
            )),
        }
    }
}

/// ρc_p and ρc_s of a material (Pa·s/m).
fn impedances(m: &Material) -> (f64, f64) {
    let rho = m.density;
    (
        (rho * (m.lambda() + 2.0 * m.shear_modulus())).sqrt(),
        (rho * m.shear_modulus()).sqrt(),
    )
}

/// The coordinate axis an interface's normal lies along, if it does: from the contact normals,
/// or from the spread of the first side's node coordinates (a plane x_a = const).
fn normal_axis(problem: &Problem, iface: &Interface) -> Option<usize> {
    if let Law::Contact(c) = &iface.law {
        let n0 = c.normal.first()?;
        let axis = (0..3).find(|&a| n0[a].abs() > 1.0 - 1e-9)?;
        return c
            .normal
            .iter()
            .all(|n| n[axis].abs() > 1.0 - 1e-9)
            .then_some(axis);
    }
    let side = iface.sides.first()?;
    let nodes = &problem.subs[side.sub].mesh.nodes;
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for &n in &side.nodes {
        for a in 0..3 {
            lo[a] = lo[a].min(nodes[n][a]);
            hi[a] = hi[a].max(nodes[n][a]);
        }
    }
    let size = (0..3).map(|a| hi[a] - lo[a]).fold(0.0f64, f64::max);
    let flat: Vec<usize> = (0..3)
        .filter(|&a| hi[a] - lo[a] <= 1e-9 * size.max(f64::MIN_POSITIVE))
        .collect();
    (flat.len() == 1).then(|| flat[0])
}

/// The component of each dof of an interface side (boundary sides list one dof per law).
fn components(iface: &Interface) -> Vec<usize> {
    match &iface.law {
        Law::Boundary(dofs) => dofs.iter().map(|d| d.component).collect(),
        _ => (0..iface.len).map(|j| j % 3).collect(),
    }
}

/// Sets the direction factors of every interface and copies them to the substructures' traces.
pub fn apply(problem: &mut Problem, directions: Directions) {
    let scales: Vec<Option<Vec<f64>>> = match directions {
        Directions::Isotropic => vec![None; problem.interfaces.len()],
        Directions::Wave => {
            let k0 = problem.default_k();
            let p = &*problem;
            p.interfaces
                .iter()
                .map(|i| wave_factors(p, i, k0))
                .collect()
        }
    };
    for (iface, s) in problem.interfaces.iter_mut().zip(scales) {
        iface.k_scale = s.unwrap_or_else(|| vec![1.0; iface.len]);
    }
    crate::interfaces::detect::copy_trace_k(&mut problem.subs, &problem.interfaces);
}

/// The wave factors of one interface (ρc_p/k0 on the normal dof, ρc_s/k0 on the others, each the
/// mean over the sides' materials), or None when its normal is not a coordinate axis.
fn wave_factors(problem: &Problem, iface: &Interface, k0: f64) -> Option<Vec<f64>> {
    let axis = normal_axis(problem, iface)?;
    let sides = iface.sides.len() as f64;
    let (zp, zs) = iface.sides.iter().fold((0.0, 0.0), |(p, s), side| {
        let (a, b) = impedances(&problem.subs[side.sub].material);
        (p + a / sides, s + b / sides)
    });
    Some(
        components(iface)
            .into_iter()
            .map(|c| if c == axis { zp / k0 } else { zs / k0 })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene;

    /// On two-blocks (steel on aluminium) the contact normal dof gets the mean over both sides
    /// of ρc_p = √(ρE (1−ν)/((1+ν)(1−2ν))) over k0 = mean √(ρE), the tangential dofs the mean
    /// of ρc_s = √(ρE/(2(1+ν))) over k0 (1.1 and 0.6 for steel alone); every substructure
    /// trace carries its interfaces' factors, and the isotropic direction puts back 1.
    #[test]
    fn wave_factors_are_the_impedance_ratios_along_and_across_the_normal() {
        let spec = scene::load("two-blocks").expect("scene");
        let mut p = scene::problem_of(&spec, "two-blocks").expect("build");
        apply(&mut p, Directions::Wave);
        let k0 = p.default_k();
        let contact = p
            .interfaces
            .iter()
            .find(|i| i.is_contact())
            .expect("contact");
        let (mut pn, mut st) = (0.0, 0.0);
        for side in &contact.sides {
            let m = p.subs[side.sub].material;
            let (e, nu, rho) = (m.young, m.poisson, m.density);
            pn += 0.5 * (rho * e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu))).sqrt() / k0;
            st += 0.5 * (rho * e / (2.0 * (1.0 + nu))).sqrt() / k0;
        }
        assert!(pn > 1.1 && st < 0.65, "{pn} {st}");
        let Law::Contact(c) = &contact.law else {
            unreachable!()
        };
        let axis = (0..3).find(|&a| c.normal[0][a].abs() > 0.5).expect("axis");
        for (j, &s) in contact.k_scale.iter().enumerate() {
            let want = if j % 3 == axis { pn } else { st };
            assert!((s - want).abs() < 1e-12, "dof {j}: {s} vs {want}");
        }
        for sub in &p.subs {
            for side in &sub.sides {
                let iface = &p.interfaces[side.interface];
                let off = iface.sides[side.side].offset;
                assert_eq!(&sub.trace_k[off..off + iface.len], &iface.k_scale[..]);
            }
            assert!(sub.trace_k.iter().all(|&s| s != 1.0), "{}", sub.name);
        }
        apply(&mut p, Directions::Isotropic);
        assert!(p.subs.iter().all(|s| s.trace_k.iter().all(|&x| x == 1.0)));
    }

    #[test]
    fn names_round_trip_and_unknown_names_are_refused() {
        for d in [Directions::Isotropic, Directions::Wave] {
            assert_eq!(Directions::parse(d.name()), Ok(d));
        }
        assert!(matches!(Directions::parse("tensor"), Err(e) if e.contains("isotropic or wave")));
    }
}
