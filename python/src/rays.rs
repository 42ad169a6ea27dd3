//! What `World.raycast` and `World.lidar_scan` refuse (issue 37, item 17): a ray that is not
//! one (a NaN or infinite origin; a direction that is zero, NaN or infinite, which has no unit
//! vector) and a pose that is not a rigid transform (a zero, scaled, sheared or mirrored
//! rotation, or a last row other than `0 0 0 1`). Before, the first gave NaN (neither a
//! refusal nor the documented `inf`), the second an empty scan.

use pyo3::PyResult;
use pyo3::exceptions::PyValueError;

/// How far a pose's rotation may be from orthonormal (each entry of `RᵀR - I`), and its last
/// row from `0 0 0 1`: 1e-6, loose enough for a rotation computed in single precision.
pub const RIGID_TOLERANCE: f64 = 1e-6;

/// Refuses the first origin or direction that does not make a ray.
pub fn check_rays(origins: &[[f64; 3]], directions: &[[f64; 3]]) -> PyResult<()> {
    if let Some(k) = origins
        .iter()
        .position(|o| !o.iter().all(|x| x.is_finite()))
    {
        let o = origins[k];
        return Err(PyValueError::new_err(format!(
            "origin {k} is ({}, {}, {}): every origin must be finite",
            o[0], o[1], o[2]
        )));
    }
    if let Some(k) = directions.iter().position(|d| {
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        !len.is_normal()
    }) {
        let d = directions[k];
        return Err(PyValueError::new_err(format!(
            "direction {k} is ({}, {}, {}): a direction must be finite and not zero (it is normalised)",
            d[0], d[1], d[2]
        )));
    }
    Ok(())
}

/// Refuses a pose whose rotation is not one (within [`RIGID_TOLERANCE`], determinant +1) or
/// whose last row is not `0 0 0 1`.
pub fn check_rigid(r: &[[f64; 3]; 3], last: [f64; 4]) -> PyResult<()> {
    let mut worst: f64 = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            let d: f64 = (0..3).map(|k| r[k][i] * r[k][j]).sum();
            worst = worst.max((d - if i == j { 1.0 } else { 0.0 }).abs());
        }
    }
    let det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1])
        - r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0])
        + r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
    let bottom = last
        .iter()
        .zip([0.0, 0.0, 0.0, 1.0])
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    if worst > RIGID_TOLERANCE || det < 0.0 || bottom > RIGID_TOLERANCE {
        return Err(PyValueError::new_err(format!(
            "pose is not a rigid transform (its rotation's RᵀR is off the identity by {worst:.3e}, determinant {det:.6}, its last row off 0 0 0 1 by {bottom:.3e}; tolerance {RIGID_TOLERANCE}): give a 4 x 4 world-from-sensor matrix [[R, t], [0 0 0 1]] with R a rotation"
        )));
    }
    Ok(())
}
