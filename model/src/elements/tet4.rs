//! Linear (constant-strain) tetrahedron, the element of meshes imported from Gmsh:
//! stiffness K_e = V Bᵀ D B with the constant strain-displacement matrix B, lumped mass ρV/4 per
//! node, stress D B u and its von Mises value (METHOD §1: lumped `M`, `K`, the same Voigt order
//! xx, yy, zz, xy, yz, zx as [`crate::elements::hex8`]). Nodes 1, 2, 3 seen from node 0 turn
//! counter-clockwise (Gmsh's order): the signed volume is positive. An inverted element
//! (negative volume) or a degenerate one (volume below 1e-12 of the cube of its longest edge) is
//! an error naming the element ([`check`]).

use crate::elements::material::Material;
use crate::error::{LopinError, Result};
use crate::mesh::{cross, dot, norm, sub, Vec3};

pub use crate::elements::hex8::von_mises;

/// The 12×12 element stiffness matrix (dof = 3·local node + component).
pub type ElementMatrix = [[f64; 12]; 12];

/// Relative volume below which an element is degenerate: V < 1e-12 · (longest edge)³.
pub const DEGENERATE_VOLUME: f64 = 1e-12;

/// Signed volume: det[x1 − x0, x2 − x0, x3 − x0] / 6.
pub fn signed_volume(x: &[Vec3; 4]) -> f64 {
    let (a, b, c) = (sub(x[1], x[0]), sub(x[2], x[0]), sub(x[3], x[0]));
    dot(a, cross(b, c)) / 6.0
}

/// Checks that element `id` of `source` is neither inverted nor degenerate; returns its volume.
pub fn check(x: &[Vec3; 4], id: usize, source: &str) -> Result<f64> {
    let v = signed_volume(x);
    let longest = (0..4)
        .flat_map(|a| (a + 1..4).map(move |b| (a, b)))
        .map(|(a, b)| norm(sub(x[a], x[b])))
        .fold(0.0, f64::max);
    let reason = if !v.is_finite() {
        Some(format!("non-finite node coordinates {x:?}"))
    } else if v.abs() <= DEGENERATE_VOLUME * longest.powi(3) {
        Some(format!(
            "degenerate tetrahedron: volume {v:.3e} m³ for a longest edge of {longest:.3e} m (nodes {x:?})"
        ))
    } else if v < 0.0 {
        Some(format!(
            "inverted tetrahedron: volume {v:.3e} m³ is negative (nodes {x:?}; nodes 1, 2, 3 must turn counter-clockwise seen from node 0)"
        ))
    } else {
        None
    };
    match reason {
        Some(reason) => Err(LopinError::BadElement {
            source_name: source.to_string(),
            element: id,
            reason,
        }),
        None => Ok(v),
    }
}

/// Cartesian gradients of the four shape functions (constant over the element): the rows of
/// the inverse of J = [x1 − x0; x2 − x0; x3 − x0] give ∇N1, ∇N2, ∇N3, and ∇N0 = −Σ the others.
fn gradients(x: &[Vec3; 4]) -> [Vec3; 4] {
    let (a, b, c) = (sub(x[1], x[0]), sub(x[2], x[0]), sub(x[3], x[0]));
    let det = dot(a, cross(b, c));
    // inverse of the matrix with rows a, b, c: its columns are (b×c, c×a, a×b)/det
    let cols = [cross(b, c), cross(c, a), cross(a, b)];
    let mut g = [[0.0; 3]; 4];
    for (n, col) in cols.iter().enumerate() {
        for k in 0..3 {
            g[n + 1][k] = col[k] / det;
            g[0][k] -= col[k] / det;
        }
    }
    g
}

/// The 6 Voigt strains of a unit displacement of node `a` along `c`.
fn strain_column(g: &[Vec3; 4], a: usize, c: usize) -> [f64; 6] {
    let [gx, gy, gz] = g[a];
    match c {
        0 => [gx, 0.0, 0.0, gy, 0.0, gz],
        1 => [0.0, gy, 0.0, gx, gz, 0.0],
        _ => [0.0, 0.0, gz, 0.0, gy, gx],
    }
}

/// Element stiffness K_e = V Bᵀ D B (the element must have passed [`check`]).
pub fn stiffness(x: &[Vec3; 4], mat: &Material) -> ElementMatrix {
    let d = mat.hooke();
    let v = signed_volume(x);
    let g = gradients(x);
    let cols: Vec<[f64; 6]> = (0..12).map(|i| strain_column(&g, i / 3, i % 3)).collect();
    let db: Vec<[f64; 6]> = cols
        .iter()
        .map(|b| std::array::from_fn(|r| (0..6).map(|s| d[r][s] * b[s]).sum()))
        .collect();
    let mut k = [[0.0; 12]; 12];
    for (i, bi) in cols.iter().enumerate() {
        for (j, dbj) in db.iter().enumerate() {
            k[i][j] = v * (0..6).map(|s| bi[s] * dbj[s]).sum::<f64>();
        }
    }
    k
}

/// Lumped nodal masses ρV/4 (the row sums of the consistent mass).
pub fn lumped_mass(x: &[Vec3; 4], mat: &Material) -> [f64; 4] {
    [0.25 * mat.density * signed_volume(x); 4]
}

/// The (constant) stress D B u for element displacements `u` (12 values).
pub fn stress(x: &[Vec3; 4], mat: &Material, u: &[f64; 12]) -> [f64; 6] {
    let g = gradients(x);
    let mut eps = [0.0; 6];
    for (i, ui) in u.iter().enumerate() {
        let b = strain_column(&g, i / 3, i % 3);
        for (e, bs) in eps.iter_mut().zip(b) {
            *e += bs * ui;
        }
    }
    mat.stress_of(&eps)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elements::material::voigt_strain;

    fn steel() -> Material {
        Material {
            young: 210e9,
            poisson: 0.3,
            density: 7800.0,
            damping: Default::default(),
        }
    }

    fn skewed() -> [Vec3; 4] {
        [
            [0.1, -0.2, 0.05],
            [1.3, 0.1, -0.1],
            [0.2, 0.9, 0.3],
            [0.4, 0.3, 1.1],
        ]
    }

    #[test]
    fn rigid_motions_produce_no_force_and_mass_is_conserved() {
        let (x, mat) = (skewed(), steel());
        let v = check(&x, 7, "test").expect("valid");
        let k = stiffness(&x, &mat);
        let scale = k.iter().flatten().fold(0.0f64, |a, b| a.max(b.abs()));
        // translations and rotations about each axis
        for mode in 0..6 {
            let mut u = [0.0; 12];
            for a in 0..4 {
                let p = x[a];
                let w = match mode {
                    0..=2 => std::array::from_fn(|c| f64::from(u8::from(c == mode))),
                    3 => [0.0, -p[2], p[1]],
                    4 => [p[2], 0.0, -p[0]],
                    _ => [-p[1], p[0], 0.0],
                };
                u[3 * a..3 * a + 3].copy_from_slice(&w);
            }
            for row in k.iter() {
                let f: f64 = row.iter().zip(&u).map(|(a, b)| a * b).sum();
                assert!(f.abs() < 1e-12 * scale, "rigid mode {mode}: force {f}");
            }
            let s = stress(&x, &mat, &u);
            assert!(s.iter().all(|v| v.abs() < 1e-12 * mat.young), "{s:?}");
        }
        let m: f64 = lumped_mass(&x, &mat).iter().sum();
        assert!((m - mat.density * v).abs() < 1e-12 * m);
        // K is symmetric
        for i in 0..12 {
            for j in 0..12 {
                assert!((k[i][j] - k[j][i]).abs() <= 1e-12 * scale);
            }
        }
    }

    #[test]
    fn uniform_strain_gives_hooke_stress_and_energy() {
        let (x, mat) = (skewed(), steel());
        // u = E x with a full strain tensor (symmetric part) plus a rotation
        let e = [[1e-3, 2e-4, -1e-4], [4e-4, -5e-4, 3e-4], [1e-4, 5e-4, 2e-4]];
        let mut u = [0.0; 12];
        for a in 0..4 {
            for i in 0..3 {
                u[3 * a + i] = (0..3).map(|j| e[i][j] * x[a][j]).sum();
            }
        }
        let eps = voigt_strain(&e);
        let want = mat.stress_of(&eps);
        let s = stress(&x, &mat, &u);
        for (a, b) in s.iter().zip(&want) {
            assert!((a - b).abs() < 1e-12 * mat.young, "{s:?} vs {want:?}");
        }
        // ½ uᵀ K u = ½ σ:ε V
        let k = stiffness(&x, &mat);
        let energy: f64 = (0..12)
            .map(|i| (0..12).map(|j| u[i] * k[i][j] * u[j]).sum::<f64>())
            .sum();
        let density: f64 = s.iter().zip(&eps).map(|(a, b)| a * b).sum();
        let v = signed_volume(&x);
        assert!((energy - density * v).abs() < 1e-10 * energy.abs());
        assert!((von_mises(&s) - von_mises(&want)).abs() < 1e-12 * mat.young);
    }

    #[test]
    fn inverted_and_degenerate_elements_are_named_errors() {
        let mut x = skewed();
        x.swap(1, 2);
        let e = check(&x, 41, "part.msh").expect_err("inverted").to_string();
        assert!(
            e.contains("part.msh") && e.contains("element 41") && e.contains("inverted"),
            "{e}"
        );
        let flat = [
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 0.5, 1e-14],
        ];
        let e = check(&flat, 3, "part.msh")
            .expect_err("degenerate")
            .to_string();
        assert!(e.contains("element 3") && e.contains("degenerate"), "{e}");
        let nan = [
            [f64::NAN; 3],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let e = check(&nan, 9, "part.msh").expect_err("nan").to_string();
        assert!(e.contains("non-finite"), "{e}");
    }
}
