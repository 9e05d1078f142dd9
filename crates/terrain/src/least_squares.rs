//! Least-squares planes `z = a + b u + c v` through scattered heights, kept as sufficient
//! statistics (count and sums of products), so that the fit of a union of point sets, and its RMS
//! residual, come in O(1) from the sums of the parts. Used for the plane series (thesis §2.1.2),
//! the local ground planes of obstacle detection (§2.5.2) and detrending.
//!
//! With centred moments `C_xy = sum(x y) - n mean(x) mean(y)`, the normal equations are
//! `[C_uu C_uv; C_uv C_vv] [b; c] = [C_uz; C_vz]`, and the residual sum of squares is
//! `C_zz - b C_uz - c C_vz`. Callers add coordinates relative to a nearby reference point so that
//! the centred moments do not suffer from cancellation.

use serde::{Deserialize, Serialize};

/// Relative size of a determinant (or variance) below which the points are taken as having no
/// spread in that direction.
const DEGENERACY_TOLERANCE: f64 = 1e-9;

/// Sufficient statistics of points `(u, v, z)`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct PlaneStats {
    n: f64,
    u: f64,
    v: f64,
    z: f64,
    uu: f64,
    vv: f64,
    zz: f64,
    uv: f64,
    uz: f64,
    vz: f64,
}

/// A fitted plane `z = z_mean + grad_u (u - u_mean) + grad_v (v - v_mean)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LsqPlane {
    /// Mean `u` of the points.
    pub u_mean: f64,
    /// Mean `v`.
    pub v_mean: f64,
    /// Mean `z`: the plane's height at the centroid.
    pub z_mean: f64,
    /// `dz/du`.
    pub grad_u: f64,
    /// `dz/dv` (zero when the points have no spread along `v`).
    pub grad_v: f64,
    /// RMS of the points' `z` about the plane.
    pub rms: f64,
}

impl LsqPlane {
    /// The plane's height at `(u, v)`.
    pub fn height(&self, u: f64, v: f64) -> f64 {
        self.z_mean + self.grad_u * (u - self.u_mean) + self.grad_v * (v - self.v_mean)
    }
}

impl PlaneStats {
    /// Adds one point.
    pub fn add(&mut self, u: f64, v: f64, z: f64) {
        self.n += 1.0;
        self.u += u;
        self.v += v;
        self.z += z;
        self.uu += u * u;
        self.vv += v * v;
        self.zz += z * z;
        self.uv += u * v;
        self.uz += u * z;
        self.vz += v * z;
    }

    /// The statistics of the union of both point sets.
    pub fn merged(&self, o: &PlaneStats) -> PlaneStats {
        PlaneStats {
            n: self.n + o.n,
            u: self.u + o.u,
            v: self.v + o.v,
            z: self.z + o.z,
            uu: self.uu + o.uu,
            vv: self.vv + o.vv,
            zz: self.zz + o.zz,
            uv: self.uv + o.uv,
            uz: self.uz + o.uz,
            vz: self.vz + o.vz,
        }
    }

    /// Number of points.
    pub fn count(&self) -> usize {
        self.n as usize
    }

    /// The least-squares plane; `None` with fewer than 3 points or no spread along `u`. Points
    /// without spread along `v` (all on one line along `u`) get `grad_v = 0`.
    ///
    /// ```
    /// use rappel_terrain::least_squares::PlaneStats;
    /// let mut st = PlaneStats::default();
    /// for (u, v) in [(0., 0.), (1., 0.), (0., 1.), (1., 1.)] {
    ///     st.add(u, v, 2.0 + 3.0 * u - v);
    /// }
    /// let p = st.fit().unwrap();
    /// assert!((p.grad_u - 3.0).abs() < 1e-12 && (p.grad_v + 1.0).abs() < 1e-12);
    /// assert!((p.height(0.0, 0.0) - 2.0).abs() < 1e-12 && p.rms < 1e-6);
    /// ```
    pub fn fit(&self) -> Option<LsqPlane> {
        if self.n < 3.0 {
            return None;
        }
        let n = self.n;
        let (mu, mv, mz) = (self.u / n, self.v / n, self.z / n);
        let cuu = (self.uu - n * mu * mu).max(0.0);
        let cvv = (self.vv - n * mv * mv).max(0.0);
        let cuv = self.uv - n * mu * mv;
        let cuz = self.uz - n * mu * mz;
        let cvz = self.vz - n * mv * mz;
        let czz = (self.zz - n * mz * mz).max(0.0);
        if cuu == 0.0 || cuu <= DEGENERACY_TOLERANCE * (cuu + cvv) {
            return None;
        }
        let det = cuu * cvv - cuv * cuv;
        let (b, c) = if cvv > 0.0 && det > DEGENERACY_TOLERANCE * cuu * cvv {
            ((cuz * cvv - cvz * cuv) / det, (cvz * cuu - cuz * cuv) / det)
        } else {
            (cuz / cuu, 0.0)
        };
        let sse = (czz - b * cuz - c * cvz).max(0.0);
        Some(LsqPlane {
            u_mean: mu,
            v_mean: mv,
            z_mean: mz,
            grad_u: b,
            grad_v: c,
            rms: (sse / n).sqrt(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merged_fit_equals_fit_of_union() {
        let pts: Vec<(f64, f64, f64)> = (0..40)
            .map(|i| {
                let (u, v) = ((i % 7) as f64, (i / 7) as f64 * 0.5);
                (
                    u,
                    v,
                    1.0 + 0.3 * u - 0.8 * v + ((i * 37) % 11) as f64 * 0.01,
                )
            })
            .collect();
        let (mut all, mut a, mut b) = (
            PlaneStats::default(),
            PlaneStats::default(),
            PlaneStats::default(),
        );
        for (i, &(u, v, z)) in pts.iter().enumerate() {
            all.add(u, v, z);
            if i < 17 {
                a.add(u, v, z)
            } else {
                b.add(u, v, z)
            }
        }
        let (f1, f2) = (all.fit().unwrap(), a.merged(&b).fit().unwrap());
        assert!((f1.grad_u - f2.grad_u).abs() < 1e-12 && (f1.rms - f2.rms).abs() < 1e-12);
        // The residual is the RMS of the perturbation about the plane: positive, small.
        assert!(f1.rms > 0.0 && f1.rms < 0.06);
        let rms_direct = (pts
            .iter()
            .map(|&(u, v, z)| (z - f1.height(u, v)).powi(2))
            .sum::<f64>()
            / pts.len() as f64)
            .sqrt();
        assert!((rms_direct - f1.rms).abs() < 1e-9);
    }

    #[test]
    fn degenerate_sets() {
        let mut line = PlaneStats::default();
        for i in 0..5 {
            line.add(i as f64, 3.0, 2.0 * i as f64);
        }
        let f = line.fit().unwrap();
        assert!((f.grad_u - 2.0).abs() < 1e-12 && f.grad_v == 0.0);
        let mut across = PlaneStats::default();
        for i in 0..5 {
            across.add(1.0, i as f64, i as f64);
        }
        assert!(across.fit().is_none());
        let mut two = PlaneStats::default();
        two.add(0.0, 0.0, 0.0);
        two.add(1.0, 1.0, 0.0);
        assert!(two.fit().is_none());
        assert_eq!(two.count(), 2);
    }
}
