//! Trilinear hexahedron: stiffness (2×2×2 Gauss), lumped mass (row sums of the consistent mass,
//! exact for the Gauss rule used) and stress at the element centre (METHOD §1: lumped `M`, `K`).

use crate::elements::material::Material;
use crate::mesh::Vec3;

/// Natural coordinates of the 8 nodes.
const XI: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// The 24×24 element stiffness matrix (dof = 3·local node + component).
pub type ElementMatrix = [[f64; 24]; 24];

/// Shape functions and their natural derivatives at (ξ, η, ζ).
fn shape(p: Vec3) -> ([f64; 8], [[f64; 3]; 8]) {
    let mut n = [0.0; 8];
    let mut dn = [[0.0; 3]; 8];
    for a in 0..8 {
        let s = [
            1.0 + XI[a][0] * p[0],
            1.0 + XI[a][1] * p[1],
            1.0 + XI[a][2] * p[2],
        ];
        n[a] = 0.125 * s[0] * s[1] * s[2];
        dn[a] = [
            0.125 * XI[a][0] * s[1] * s[2],
            0.125 * XI[a][1] * s[0] * s[2],
            0.125 * XI[a][2] * s[0] * s[1],
        ];
    }
    (n, dn)
}

/// Cartesian shape-function gradients and det J at a natural point.
fn gradients(x: &[Vec3; 8], p: Vec3) -> ([f64; 8], [[f64; 3]; 8], f64) {
    let (n, dn) = shape(p);
    // J[i][j] = d x_j / d ξ_i
    let mut j = [[0.0; 3]; 3];
    for a in 0..8 {
        for r in 0..3 {
            for c in 0..3 {
                j[r][c] += dn[a][r] * x[a][c];
            }
        }
    }
    let det = j[0][0] * (j[1][1] * j[2][2] - j[1][2] * j[2][1])
        - j[0][1] * (j[1][0] * j[2][2] - j[1][2] * j[2][0])
        + j[0][2] * (j[1][0] * j[2][1] - j[1][1] * j[2][0]);
    let inv = [
        [
            (j[1][1] * j[2][2] - j[1][2] * j[2][1]) / det,
            (j[0][2] * j[2][1] - j[0][1] * j[2][2]) / det,
            (j[0][1] * j[1][2] - j[0][2] * j[1][1]) / det,
        ],
        [
            (j[1][2] * j[2][0] - j[1][0] * j[2][2]) / det,
            (j[0][0] * j[2][2] - j[0][2] * j[2][0]) / det,
            (j[0][2] * j[1][0] - j[0][0] * j[1][2]) / det,
        ],
        [
            (j[1][0] * j[2][1] - j[1][1] * j[2][0]) / det,
            (j[0][1] * j[2][0] - j[0][0] * j[2][1]) / det,
            (j[0][0] * j[1][1] - j[0][1] * j[1][0]) / det,
        ],
    ];
    // dN/dx_c = Σ_r invJ[c][r] dN/dξ_r
    let mut g = [[0.0; 3]; 8];
    for a in 0..8 {
        for c in 0..3 {
            g[a][c] = (0..3).map(|r| inv[c][r] * dn[a][r]).sum();
        }
    }
    (n, g, det)
}

/// Strain-displacement matrix B (6×24, Voigt order xx, yy, zz, xy, yz, zx).
fn strain_matrix(g: &[[f64; 3]; 8]) -> [[f64; 24]; 6] {
    let mut b = [[0.0; 24]; 6];
    for a in 0..8 {
        let [gx, gy, gz] = g[a];
        let c = 3 * a;
        b[0][c] = gx;
        b[1][c + 1] = gy;
        b[2][c + 2] = gz;
        b[3][c] = gy;
        b[3][c + 1] = gx;
        b[4][c + 1] = gz;
        b[4][c + 2] = gy;
        b[5][c] = gz;
        b[5][c + 2] = gx;
    }
    b
}

/// The 2×2×2 Gauss points (weights 1).
fn gauss_points() -> impl Iterator<Item = Vec3> {
    let q = 1.0 / 3f64.sqrt();
    (0..8).map(move |i| {
        [
            if i & 1 == 0 { -q } else { q },
            if i & 2 == 0 { -q } else { q },
            if i & 4 == 0 { -q } else { q },
        ]
    })
}

/// Element stiffness K_e = Σ_g Bᵀ D B det J.
pub fn stiffness(x: &[Vec3; 8], mat: &Material) -> Box<ElementMatrix> {
    let d = mat.hooke();
    let mut k = Box::new([[0.0; 24]; 24]);
    for p in gauss_points() {
        let (_, g, det) = gradients(x, p);
        let b = strain_matrix(&g);
        // db = D B (6×24)
        let mut db = [[0.0; 24]; 6];
        for r in 0..6 {
            for c in 0..24 {
                db[r][c] = (0..6).map(|s| d[r][s] * b[s][c]).sum();
            }
        }
        for i in 0..24 {
            for j in 0..24 {
                let v: f64 = (0..6).map(|s| b[s][i] * db[s][j]).sum();
                k[i][j] += v * det;
            }
        }
    }
    k
}

/// Lumped nodal masses: m_a = Σ_g ρ N_a det J (row sums of the consistent mass).
pub fn lumped_mass(x: &[Vec3; 8], mat: &Material) -> [f64; 8] {
    let mut m = [0.0; 8];
    for p in gauss_points() {
        let (n, _, det) = gradients(x, p);
        for a in 0..8 {
            m[a] += mat.density * n[a] * det;
        }
    }
    m
}

/// The Jacobian determinant at each of the eight corners (the reference cube's vertices, in the
/// node order): all positive for a valid element; a twisted or folded hexahedron has a corner
/// where it is not, even when its volume is positive.
pub fn corner_jacobians(x: &[Vec3; 8]) -> [f64; 8] {
    std::array::from_fn(|a| gradients(x, XI[a]).2)
}

/// Element volume.
pub fn volume(x: &[Vec3; 8]) -> f64 {
    gauss_points().map(|p| gradients(x, p).2).sum()
}

/// Stress (Voigt order xx, yy, zz, xy, yz, zx) at the element centre for element displacements
/// `u` (24 values).
pub fn centre_stress(x: &[Vec3; 8], mat: &Material, u: &[f64; 24]) -> [f64; 6] {
    let (_, g, _) = gradients(x, [0.0; 3]);
    let b = strain_matrix(&g);
    let d = mat.hooke();
    let mut eps = [0.0; 6];
    for (r, e) in eps.iter_mut().enumerate() {
        *e = (0..24).map(|c| b[r][c] * u[c]).sum();
    }
    let mut s = [0.0; 6];
    for (r, v) in s.iter_mut().enumerate() {
        *v = (0..6).map(|c| d[r][c] * eps[c]).sum();
    }
    s
}

/// Von Mises equivalent stress of a Voigt stress vector.
pub fn von_mises(s: &[f64; 6]) -> f64 {
    let [xx, yy, zz, xy, yz, zx] = *s;
    (0.5 * ((xx - yy).powi(2) + (yy - zz).powi(2) + (zz - xx).powi(2))
        + 3.0 * (xy * xy + yz * yz + zx * zx))
        .sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn brick(h: [f64; 3]) -> [Vec3; 8] {
        let mut x = [[0.0; 3]; 8];
        for a in 0..8 {
            for c in 0..3 {
                x[a][c] = 0.5 * (XI[a][c] + 1.0) * h[c];
            }
        }
        x
    }

    #[test]
    fn rigid_motions_produce_no_force_and_mass_is_conserved() {
        let x = brick([0.3, 0.2, 0.1]);
        let mat = Material {
            young: 2.0,
            poisson: 0.3,
            density: 5.0,
            damping: Default::default(),
        };
        let k = stiffness(&x, &mat);
        // translation along y and rotation about z
        for mode in 0..2 {
            let mut u = [0.0; 24];
            for a in 0..8 {
                if mode == 0 {
                    u[3 * a + 1] = 1.0;
                } else {
                    u[3 * a] = -x[a][1];
                    u[3 * a + 1] = x[a][0];
                }
            }
            for row in k.iter() {
                let f: f64 = row.iter().zip(&u).map(|(a, b)| a * b).sum();
                assert!(f.abs() < 1e-12, "rigid mode {mode} gives force {f}");
            }
        }
        let m: f64 = lumped_mass(&x, &mat).iter().sum();
        assert!((m - 5.0 * 0.3 * 0.2 * 0.1).abs() < 1e-14);
        assert!((volume(&x) - 0.006).abs() < 1e-15);
    }

    #[test]
    fn von_mises_of_uniaxial_and_pure_shear() {
        assert!((von_mises(&[-3.0, 0.0, 0.0, 0.0, 0.0, 0.0]) - 3.0).abs() < 1e-15);
        assert!((von_mises(&[0.0, 0.0, 0.0, 2.0, 0.0, 0.0]) - 2.0 * 3f64.sqrt()).abs() < 1e-15);
        assert!(von_mises(&[5.0, 5.0, 5.0, 0.0, 0.0, 0.0]).abs() < 1e-15);
    }

    #[test]
    fn uniaxial_strain_gives_hooke_stress() {
        let x = brick([1.0, 1.0, 1.0]);
        let mat = Material {
            young: 100.0,
            poisson: 0.25,
            density: 1.0,
            damping: Default::default(),
        };
        let mut u = [0.0; 24];
        for a in 0..8 {
            u[3 * a] = 1e-3 * x[a][0];
        }
        let s = centre_stress(&x, &mat, &u);
        let l = mat.lambda();
        let g = mat.shear_modulus();
        assert!((s[0] - (l + 2.0 * g) * 1e-3).abs() < 1e-12);
        assert!((s[1] - l * 1e-3).abs() < 1e-12);
        assert!(s[3].abs() < 1e-12);
        // energy ½ uᵀKu equals ½ σ:ε V
        let k = stiffness(&x, &mat);
        let e: f64 = (0..24)
            .map(|i| (0..24).map(|j| u[i] * k[i][j] * u[j]).sum::<f64>())
            .sum();
        assert!((0.5 * e - 0.5 * s[0] * 1e-3).abs() < 1e-12);
    }
}
