//! Small dense symmetric positive definite solves (Cholesky, row-major): the Anderson mixing's
//! least-squares normal equations (a few unknowns, `lopin_core::stages::acceleration`) and element-level
//! checks in tests. Sparse systems go through [`crate::linalg::factor`].

/// Solves A x = b for a symmetric positive definite A (row-major n×n, n = b.len()).
pub fn solve_spd(mut a: Vec<f64>, mut b: Vec<f64>) -> Vec<f64> {
    let n = b.len();
    for j in 0..n {
        let d = (a[j * n + j] - (0..j).map(|k| a[j * n + k] * a[j * n + k]).sum::<f64>()).sqrt();
        a[j * n + j] = d;
        for i in j + 1..n {
            let s: f64 = (0..j).map(|k| a[i * n + k] * a[j * n + k]).sum();
            a[i * n + j] = (a[i * n + j] - s) / d;
        }
    }
    for i in 0..n {
        let s: f64 = (0..i).map(|k| a[i * n + k] * b[k]).sum();
        b[i] = (b[i] - s) / a[i * n + i];
    }
    for i in (0..n).rev() {
        let s: f64 = (i + 1..n).map(|k| a[k * n + i] * b[k]).sum();
        b[i] = (b[i] - s) / a[i * n + i];
    }
    b
}

#[cfg(test)]
mod tests {
    #[test]
    fn solves_a_small_spd_system() {
        // A = [[4, 1], [1, 3]], x = (1, −2)
        let x = super::solve_spd(vec![4.0, 1.0, 1.0, 3.0], vec![2.0, -5.0]);
        assert!(
            (x[0] - 1.0).abs() < 1e-15 && (x[1] + 2.0).abs() < 1e-15,
            "{x:?}"
        );
    }
}
