//! Patch test of the linear tetrahedron (`lopin_core::elements::tet4`): on an irregular
//! tetrahedral mesh of a cube (3 × 3 × 3 cells, each split into 6 tetrahedra along its main
//! diagonal, the 8 interior nodes moved by up to 0.3 of a cell in every direction), the
//! displacement u = E x prescribed on the boundary nodes must give u = E x at the interior nodes
//! and the stress D ε(E) in every element, to 1e-12 relative: a conforming element reproduces
//! any uniform strain state exactly.

use lopin_core::elements::material::{voigt_strain, Material};
use lopin_core::elements::tet4;
use lopin_core::linalg::dense::solve_spd;
use lopin_core::mesh::Vec3;
use lopin_core::mesh::KUHN_PATHS;

const N: usize = 4; // nodes per edge

fn node(i: usize, j: usize, k: usize) -> usize {
    i + N * (j + N * k)
}

/// Nodes (interior ones moved by a fixed pseudo-random offset) and tetrahedra.
fn mesh() -> (Vec<Vec3>, Vec<[usize; 4]>) {
    let h = 1.0 / (N - 1) as f64;
    let mut seed = 12345u64;
    let mut rand = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let mut x = Vec::new();
    for k in 0..N {
        for j in 0..N {
            for i in 0..N {
                let interior = [i, j, k].iter().all(|&a| a > 0 && a < N - 1);
                let mut p = [i as f64 * h, j as f64 * h, k as f64 * h];
                if interior {
                    for c in &mut p {
                        *c += 0.6 * h * rand();
                    }
                }
                x.push(p);
            }
        }
    }
    // Kuhn split: the six paths from corner 000 to 111 along the axes, in every order
    let mut tets = Vec::new();
    for k in 0..N - 1 {
        for j in 0..N - 1 {
            for i in 0..N - 1 {
                for p in KUHN_PATHS {
                    let mut c = [i, j, k];
                    let mut t = [node(c[0], c[1], c[2]); 4];
                    for (s, axis) in p.iter().enumerate() {
                        c[*axis] += 1;
                        t[s + 1] = node(c[0], c[1], c[2]);
                    }
                    // odd permutations give the opposite orientation
                    if tet4::signed_volume(&t.map(|n| x[n])) < 0.0 {
                        t.swap(1, 2);
                    }
                    tets.push(t);
                }
            }
        }
    }
    (x, tets)
}

#[test]
fn uniform_strain_is_reproduced_on_an_irregular_tetrahedral_mesh() {
    let (x, tets) = mesh();
    assert_eq!(tets.len(), 6 * 27);
    let mat = Material {
        young: 70e9,
        poisson: 0.33,
        density: 2700.0,
        damping: Default::default(),
    };
    let mut volume = 0.0;
    for (id, t) in tets.iter().enumerate() {
        volume += tet4::check(&t.map(|n| x[n]), id + 1, "patch").expect("valid element");
    }
    assert!((volume - 1.0).abs() < 1e-13, "volume {volume}");
    let e = [
        [1e-3, 3e-4, -2e-4],
        [1e-4, -6e-4, 5e-4],
        [-3e-4, 2e-4, 4e-4],
    ];
    let exact = |p: Vec3| -> Vec3 { std::array::from_fn(|i| (0..3).map(|j| e[i][j] * p[j]).sum()) };
    // interior dofs numbered 0.., boundary dofs prescribed
    let interior: Vec<usize> = (0..x.len())
        .filter(|&n| {
            let (i, j, k) = (n % N, (n / N) % N, n / (N * N));
            [i, j, k].iter().all(|&a| a > 0 && a < N - 1)
        })
        .collect();
    let mut slot = vec![None; x.len()];
    for (s, &n) in interior.iter().enumerate() {
        slot[n] = Some(s);
    }
    let m = 3 * interior.len();
    let (mut a, mut b) = (vec![0.0; m * m], vec![0.0; m]);
    for t in &tets {
        let k = tet4::stiffness(&t.map(|n| x[n]), &mat);
        for (la, &na) in t.iter().enumerate() {
            let Some(sa) = slot[na] else { continue };
            for (lb, &nb) in t.iter().enumerate() {
                for c in 0..3 {
                    for d in 0..3 {
                        let kv = k[3 * la + c][3 * lb + d];
                        match slot[nb] {
                            Some(sb) => a[(3 * sa + c) * m + 3 * sb + d] += kv,
                            None => b[3 * sa + c] -= kv * exact(x[nb])[d],
                        }
                    }
                }
            }
        }
    }
    let y = solve_spd(a, b);
    let scale = x
        .iter()
        .flat_map(|&p| exact(p))
        .fold(0.0f64, |s, v| s.max(v.abs()));
    let mut worst = 0.0f64;
    for (s, &n) in interior.iter().enumerate() {
        for c in 0..3 {
            worst = worst.max((y[3 * s + c] - exact(x[n])[c]).abs() / scale);
        }
    }
    println!("patch test: max interior displacement error {worst:.2e} (relative)");
    assert!(worst < 1e-12, "interior displacement error {worst:e}");
    // the stress of every element is D ε(E)
    let want = mat.stress_of(&voigt_strain(&e));
    let smax = want.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    let mut worst_stress = 0.0f64;
    for t in &tets {
        let mut u = [0.0; 12];
        for (l, &n) in t.iter().enumerate() {
            let v = match slot[n] {
                Some(s) => [y[3 * s], y[3 * s + 1], y[3 * s + 2]],
                None => exact(x[n]),
            };
            u[3 * l..3 * l + 3].copy_from_slice(&v);
        }
        let s = tet4::stress(&t.map(|n| x[n]), &mat, &u);
        for (a, w) in s.iter().zip(&want) {
            worst_stress = worst_stress.max((a - w).abs() / smax);
        }
    }
    println!("patch test: max element stress error {worst_stress:.2e} (relative)");
    assert!(worst_stress < 1e-12, "stress error {worst_stress:e}");
}
