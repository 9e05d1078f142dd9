//! Regression cases of the mechanics crate (issue 5, item 8): rope statics against closed forms
//! (thesis Figs. 3.4-3.9), Kumar's tension-limited stability sweep (Kumar Fig. 5) and sanity checks
//! of the Axel wheel/tether QP (Paton §IV-C). Each case puts the measured value beside a reference
//! obtained independently (a closed form or the papers' stated result). The geometry the papers do
//! not give numerically is chosen here and documented in `docs/mechanics.md`.

use super::case::Case;
use rappel::mechanics::axel::{Axel, AxelParams, BoomMode, tether_tension_estimate};
use rappel::mechanics::four_wheel::FourWheelRover;
use rappel::mechanics::heavy_rope::{HeavyRope, RopeOutcome, TensionBranch};
use rappel::mechanics::nalgebra::{Point2, Point3, Vector3};
use rappel::mechanics::ode::OdeSettings;
use rappel::mechanics::robot::{PlanarPose, STANDARD_GRAVITY, SlopePlane, TetherSpec, place};
use rappel::mechanics::stability_map::{
    AnchorSource, GridSpec, Heading, MapPlane, PoseVerdict, stability_map,
};
use rappel::mechanics::stability_qp::StabilityQp;
use rappel::mechanics::surface_curve::{CurveJet, Helix, PlaneLine, SurfaceCurve};
use rappel::mechanics::tension_lp::{FrictionPyramid, TensionLimitedLp};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

const SUITE: &str = "mechanics";

/// The integrator tolerances of the rope cases.
fn ode() -> Result<OdeSettings, String> {
    OdeSettings::new()
        .with_tolerances(1e-10, 1e-12)
        .map_err(|e| e.to_string())
}

/// Integrates the limiting tension on `branch` along `curve`; an error if the rope slips.
fn profile(
    rope: &HeavyRope,
    curve: &dyn SurfaceCurve,
    t0: f64,
    branch: TensionBranch,
) -> Result<(Vec<f64>, Vec<f64>), String> {
    match rope
        .limit_tension(curve, t0, branch)
        .map_err(|e| e.to_string())?
    {
        RopeOutcome::Holds(p) => Ok((p.s, p.tension)),
        RopeOutcome::Slips { at, reason } => Err(format!("rope slipped at s = {at} ({reason:?})")),
    }
}

/// Largest relative error of a profile against `exact(s)`.
fn max_rel_err(s: &[f64], t: &[f64], exact: impl Fn(f64) -> f64) -> f64 {
    s.iter()
        .zip(t)
        .map(|(s, t)| ((t - exact(*s)) / exact(*s)).abs())
        .fold(0.0, f64::max)
}

/// Thesis Fig. 3.4: a weightless rope on a capstan of radius 0.5 m, μ = 0.4, contact angle 0 to
/// π/2, both limits against `T_0 e^{±μζ}`.
fn capstan() -> Result<Vec<Case>, String> {
    let (r, mu, t0) = (0.5, 0.4, 100.0);
    let curve = Helix::new(r, 0.0, FRAC_PI_2).map_err(|e| e.to_string())?;
    let rope = HeavyRope::weightless(mu, ode()?).map_err(|e| e.to_string())?;
    let mut cases = Vec::new();
    for (branch, sign, label) in [
        (TensionBranch::Growing, 1.0, "upper"),
        (TensionBranch::Decaying, -1.0, "lower"),
    ] {
        let (s, t) = profile(&rope, &curve, t0, branch)?;
        let err = max_rel_err(&s, &t, |s| t0 * (sign * mu * s / r).exp());
        cases.push(Case::closed_form(
            SUITE,
            format!("capstan R 0.5 m, mu 0.4, zeta 0..pi/2: {label} limit, max rel. error"),
            format!("{err:.1e}"),
            "<= 1e-6 vs T0 e^(±mu zeta)",
            err <= 1e-6,
        ));
    }
    Ok(cases)
}

/// Thesis Fig. 3.5: a weightless rope along a helix (R = 1 m, pitch 1 m, T_0 = 45 N) over a
/// quarter turn; Konyukhov's closed form `T = T_0 e^{μ |κ_n| s}`, `|κ_n| = R/(R² + c²)`. The
/// curve is compared at every fifth of the turn (each a run on the helix cut there) and over the
/// whole profile.
fn helix() -> Result<Vec<Case>, String> {
    let (r, pitch, mu, t0) = (1.0, 1.0, 0.4, 45.0);
    let c: f64 = pitch / TAU;
    let kn = r / (r * r + c * c);
    let exact = |s: f64| t0 * (mu * kn * s).exp();
    let rope = HeavyRope::weightless(mu, ode()?).map_err(|e| e.to_string())?;
    let curve = Helix::new(r, pitch, FRAC_PI_2).map_err(|e| e.to_string())?;
    let (s, t) = profile(&rope, &curve, t0, TensionBranch::Growing)?;
    let err = max_rel_err(&s, &t, exact);
    let mut at = Vec::new();
    for k in 1..=5 {
        let cut = Helix::new(r, pitch, FRAC_PI_2 * k as f64 / 5.0).map_err(|e| e.to_string())?;
        let (_, t) = profile(&rope, &cut, t0, TensionBranch::Growing)?;
        at.push((cut.length(), t.last().copied().unwrap_or(f64::NAN)));
    }
    let worst = at
        .iter()
        .map(|(s, t)| ((t - exact(*s)) / exact(*s)).abs())
        .fold(err, f64::max);
    Ok(vec![Case::closed_form(
        SUITE,
        "Fig. 3.5 helix R 1 m, pitch 1 m, T0 45 N, 0..pi/2: tension at s = L/5 .. L, N",
        format!(
            "{} (max rel. error {worst:.1e})",
            at.iter()
                .map(|(_, t)| format!("{t:.4}"))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        format!(
            "{} (T0 e^(mu R s/(R^2+c^2)), Konyukhov; rel. 1e-6 along the profile)",
            at.iter()
                .map(|(s, _)| format!("{:.4}", exact(*s)))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        worst <= 1e-6,
    )])
}

/// Thesis Figs. 3.6-3.7: a 100 g/m rope straight across a plane tilted 30°, 30° off the fall line,
/// 10 m, T_0 = 45 N, μ = 0.4. With `κ = 0` eq. 3.14' integrates to
/// `T(s) = T_0 + ρ g s (sin η cos β + sqrt(μ² cos² η - sin² η sin² β))`, compared every 2.5 m
/// (each a run on the line cut there) and over the whole profile.
fn heavy_rope_on_tilted_plane() -> Result<Vec<Case>, String> {
    let (eta, beta, rho, mu, t0, len): (f64, f64, f64, f64, f64, f64) =
        (30f64.to_radians(), 30f64.to_radians(), 0.1, 0.4, 45.0, 10.0);
    let g = STANDARD_GRAVITY;
    let rope = heavy_rope(mu, rho)?;
    let rate = rho
        * g
        * (eta.sin() * beta.cos()
            + (mu * mu * eta.cos().powi(2) - (eta.sin() * beta.sin()).powi(2)).sqrt());
    let (s, t) = profile(
        &rope,
        &line_on_plane(eta, beta, len)?,
        t0,
        TensionBranch::Growing,
    )?;
    let mut worst = max_rel_err(&s, &t, |s| t0 + rate * s);
    let mut measured = Vec::new();
    let mut reference = Vec::new();
    for k in 1..=4 {
        let l = len * k as f64 / 4.0;
        let (_, t) = profile(
            &rope,
            &line_on_plane(eta, beta, l)?,
            t0,
            TensionBranch::Growing,
        )?;
        let end = t.last().copied().unwrap_or(f64::NAN);
        worst = worst.max(((end - (t0 + rate * l)) / (t0 + rate * l)).abs());
        measured.push(format!("{end:.4}"));
        reference.push(format!("{:.4}", t0 + rate * l));
    }
    Ok(vec![Case::closed_form(
        SUITE,
        "Fig. 3.7 heavy rope 100 g/m, 30 deg plane, T0 45 N: tension at s = 2.5, 5, 7.5, 10 m, N",
        format!("{} (max rel. error {worst:.1e})", measured.join(", ")),
        format!(
            "{} (eq. 3.14' with kappa = 0, integrated by hand; rel. 1e-9)",
            reference.join(", ")
        ),
        worst <= 1e-9,
    )])
}

/// A straight line of length `len` up a plane of slope `eta`, at `beta` from the fall line.
fn line_on_plane(eta: f64, beta: f64, len: f64) -> Result<PlaneLine, String> {
    let (normal, up, across) = plane_axes(eta);
    PlaneLine::new(
        Point3::origin(),
        up * beta.cos() + across * beta.sin(),
        normal,
        len,
    )
    .map_err(|e| e.to_string())
}

/// A rope of `rho` kg/m with friction `mu` under Earth gravity.
fn heavy_rope(mu: f64, rho: f64) -> Result<HeavyRope, String> {
    HeavyRope::new(mu, rho, Vector3::new(0.0, 0.0, -STANDARD_GRAVITY), ode()?)
        .map_err(|e| e.to_string())
}

/// Outward normal, up-slope and across-slope unit vectors of a plane of slope `eta`.
fn plane_axes(eta: f64) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
    (
        Vector3::new(0.0, -eta.sin(), eta.cos()),
        Vector3::new(0.0, eta.cos(), eta.sin()),
        Vector3::x(),
    )
}

/// Thesis Figs. 3.8-3.9: a heavy (100 g/m) tether running up a steep (60°) then a shallow (30°)
/// slope at 20° to the fall line (a geodesic keeps that angle across the edge), loaded with 539 N
/// at the robot end (`s = 0`). On a plane `κ = 0`, so a straight tether sticks iff
/// `μ >= tan η sin β` whatever its tension (closed form of `D >= 0`): the verdict rows. The
/// tension rows depend on the load: the whole tether over the edge at μ = 0.7 (sticks on both),
/// and the shallow slope alone at μ = 0.31 (where the thesis' Fig. 3.9 shows only that slope),
/// against eq. 3.14' integrated here by a fixed-step RK4 written for this geometry
/// ([`two_slopes_reference`]), not by the code under test.
fn two_slopes() -> Result<Vec<Case>, String> {
    let (beta, rho, len) = (20f64.to_radians(), 0.1, 5.0);
    let mut cases = Vec::new();
    for mu in [0.31, 0.7] {
        for (name, eta_deg) in [("shallow 30 deg", 30.0f64), ("steep 60 deg", 60.0)] {
            let eta = eta_deg.to_radians();
            let line = line_on_plane(eta, beta, len)?;
            let rope = heavy_rope(mu, rho)?;
            let sticks = matches!(
                rope.limit_tension(&line, LOAD_N, TensionBranch::Growing)
                    .map_err(|e| e.to_string())?,
                RopeOutcome::Holds(_)
            );
            let threshold = eta.tan() * beta.sin();
            let expect = mu >= threshold;
            let word = |b: bool| if b { "sticks" } else { "slips" };
            cases.push(Case::paper_verdict(
                SUITE,
                format!("Fig. 3.9 two slopes, mu {mu}: {name}"),
                word(sticks),
                format!(
                    "{} (thesis §3.3.4; mu* = tan(eta) sin(beta) = {threshold:.3}, any load)",
                    word(expect)
                ),
                sticks == expect,
            ));
        }
    }
    // The tension curves: (label, mu, the slopes the tether runs over, bottom first).
    let runs: [(&str, f64, &[f64]); 2] = [
        ("steep 60 deg, edge, shallow 30 deg", 0.7, &[60.0, 30.0]),
        ("shallow 30 deg alone", 0.31, &[30.0]),
    ];
    for (label, mu, slopes) in runs {
        let slopes: Vec<f64> = slopes.iter().map(|d: &f64| d.to_radians()).collect();
        // Steps no longer than a fifth of the rounded edge: an adaptive step taken from the
        // straight slope across the edge would put trial stages where the tension grows at
        // mu cos^2(beta) T / r (about 7,000 N/m), and the integrator's stage combination could
        // read a negative trial tension as slack.
        let settings = ode()?
            .with_max_step(EDGE_RADIUS / 5.0)
            .map_err(|e| e.to_string())?;
        let rope = HeavyRope::new(mu, rho, Vector3::new(0.0, 0.0, -STANDARD_GRAVITY), settings)
            .map_err(|e| e.to_string())?;
        let full = TwoSlopes::new(&slopes, beta, len, EDGE_RADIUS, None);
        let marks = full.marks();
        let (mut measured, mut reference, mut worst) = (Vec::new(), Vec::new(), 0.0f64);
        for &s in &marks {
            let cut = TwoSlopes::new(&slopes, beta, len, EDGE_RADIUS, Some(s));
            let (_, t) = profile(&rope, &cut, LOAD_N, TensionBranch::Growing)?;
            let got = t.last().copied().unwrap_or(f64::NAN);
            let want = two_slopes_reference(&slopes, beta, len, EDGE_RADIUS, rho, mu, LOAD_N, s);
            worst = worst.max(((got - want) / want).abs());
            measured.push(format!("{got:.3}"));
            reference.push(format!("{want:.3}"));
        }
        cases.push(Case::closed_form(
            SUITE,
            format!(
                "Fig. 3.9 two slopes, {LOAD_N} N, mu {mu}, {label}: tension at s = {} m, N",
                marks
                    .iter()
                    .map(|s| format!("{s:.2}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            format!("{} (max rel. error {worst:.1e})", measured.join(", ")),
            format!(
                "{} (eq. 3.14' by RK4 here, edge rounded to {EDGE_RADIUS} m; rel. 1e-6)",
                reference.join(", ")
            ),
            worst <= 1e-6,
        ));
    }
    Ok(cases)
}

/// The load at the robot end of the Figs. 3.8-3.9 tether: Axel's 55 kg hanging (thesis §3.3.4).
const LOAD_N: f64 = 539.0;
/// The radius the edge between the two slopes is rounded to (a cylinder tangent to both), m:
/// small against the 5 m slopes, large enough for the integrator to step through.
const EDGE_RADIUS: f64 = 0.05;

/// Outward normal of a plane of slope `phi` in the `(y, z)` section (`y` up the fall line).
fn section_normal(phi: f64) -> Vector3<f64> {
    Vector3::new(0.0, -phi.sin(), phi.cos())
}

/// Up-slope unit vector of a plane of slope `phi`.
fn section_up(phi: f64) -> Vector3<f64> {
    Vector3::new(0.0, phi.cos(), phi.sin())
}

/// A geodesic at `beta` to the fall line up a series of planes of slopes `slopes` (bottom first,
/// each `len` long along the tether), every edge rounded to a cylinder of radius `radius` on
/// which the tether is a helix; arc length from the bottom, optionally cut at `cut`.
struct TwoSlopes {
    /// `(start s, end s, piece)`: a plane of slope `phi`, or an edge from `phi` to `phi2`.
    pieces: Vec<(f64, f64, Piece)>,
    beta: f64,
    radius: f64,
    length: f64,
}

#[derive(Clone, Copy)]
enum Piece {
    Plane(f64),
    Edge(f64, f64),
}

impl TwoSlopes {
    fn new(slopes: &[f64], beta: f64, len: f64, radius: f64, cut: Option<f64>) -> Self {
        let mut pieces = Vec::new();
        let mut s = 0.0;
        for (i, &phi) in slopes.iter().enumerate() {
            pieces.push((s, s + len, Piece::Plane(phi)));
            s += len;
            if let Some(&next) = slopes.get(i + 1) {
                let l = radius * (phi - next).abs() / beta.cos();
                pieces.push((s, s + l, Piece::Edge(phi, next)));
                s += l;
            }
        }
        TwoSlopes {
            pieces,
            beta,
            radius,
            length: cut.unwrap_or(s).min(s),
        }
    }

    /// Where the curve is compared: the middle and both ends of every piece.
    fn marks(&self) -> Vec<f64> {
        let mut m = Vec::new();
        for &(a, b, p) in &self.pieces {
            if matches!(p, Piece::Plane(_)) {
                m.push(0.5 * (a + b));
            }
            m.push(b);
        }
        m
    }

    fn piece(&self, s: f64) -> (f64, Piece) {
        let k = self
            .pieces
            .iter()
            .position(|(_, b, _)| s <= *b)
            .unwrap_or(self.pieces.len() - 1);
        (s - self.pieces[k].0, self.pieces[k].2)
    }

    /// The section angle at `s`: the plane's slope, or on an edge the current normal's angle.
    fn angle(&self, s: f64) -> (f64, bool) {
        match self.piece(s) {
            (_, Piece::Plane(phi)) => (phi, false),
            (u, Piece::Edge(a, b)) => (
                a + (b - a).signum() * u * self.beta.cos() / self.radius,
                true,
            ),
        }
    }
}

impl SurfaceCurve for TwoSlopes {
    fn length(&self) -> f64 {
        self.length
    }

    fn point(&self, s: f64) -> Point3<f64> {
        // Only the jet enters the rope statics; the position is integrated from the tangent.
        let (phi, _) = self.angle(s);
        Point3::origin() + (section_up(phi) * self.beta.cos() + Vector3::x() * self.beta.sin()) * s
    }

    fn jet(&self, s: f64) -> CurveJet {
        let (phi, on_edge) = self.angle(s);
        let n = section_normal(phi);
        let kappa = if on_edge {
            self.beta.cos().powi(2) / self.radius
        } else {
            0.0
        };
        CurveJet {
            velocity: section_up(phi) * self.beta.cos() + Vector3::x() * self.beta.sin(),
            acceleration: -n * kappa,
            surface_normal: n,
        }
    }
}

/// Eq. 3.14' (thesis §3.2.3 with the load's sign of `docs/mechanics.md`) along [`TwoSlopes`],
/// written out for this geometry and integrated by classical RK4 with fixed steps that land on
/// every piece boundary: on a plane of slope `φ`, `dT/ds = ρ g sin φ cos β + sqrt(μ² (ρ g cos φ)²
/// - (ρ g sin φ sin β)²)`; on an edge, `κ_n = -cos² β / r`, so `F_n = T cos² β / r + ρ g cos φ`
/// and `dT/ds = ρ g sin φ cos β + sqrt(μ² F_n² - (ρ g sin φ sin β)²)`, `φ` turning at
/// `cos β / r`. The tension at `s_end`, starting from `t0` at the bottom.
#[allow(clippy::too_many_arguments)]
fn two_slopes_reference(
    slopes: &[f64],
    beta: f64,
    len: f64,
    radius: f64,
    rho: f64,
    mu: f64,
    t0: f64,
    s_end: f64,
) -> f64 {
    let w = rho * STANDARD_GRAVITY;
    let curve = TwoSlopes::new(slopes, beta, len, radius, None);
    let rate = |s: f64, t: f64| {
        let (phi, on_edge) = curve.angle(s);
        let f_n = if on_edge {
            t * beta.cos().powi(2) / radius + w * phi.cos()
        } else {
            w * phi.cos()
        };
        let lateral = w * phi.sin() * beta.sin();
        w * phi.sin() * beta.cos() + (mu * mu * f_n * f_n - lateral * lateral).max(0.0).sqrt()
    };
    let mut t = t0;
    for &(a, b, p) in &curve.pieces {
        if a >= s_end {
            break;
        }
        let b = b.min(s_end);
        let steps = match p {
            Piece::Plane(_) => 2000,
            Piece::Edge(..) => 20_000,
        };
        let h = (b - a) / steps as f64;
        for k in 0..steps {
            // Sample strictly inside the piece so a boundary is never read from its neighbour.
            let s = a + k as f64 * h;
            let inside = |x: f64| x.clamp(a + 1e-12, b - 1e-12);
            let k1 = rate(inside(s), t);
            let k2 = rate(inside(s + h / 2.0), t + h / 2.0 * k1);
            let k3 = rate(inside(s + h / 2.0), t + h / 2.0 * k2);
            let k4 = rate(inside(s + h), t + h * k3);
            t += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        }
    }
    t
}

/// Kumar §IV geometry: robot 2 on S1 (55°) or S2 (65°), each 8 m long, below the flat top S0 where
/// the tether's last obstacle anchor sits 3 m behind the S0/S1 ridge and 4 m right of centre. The
/// tether runs straight in the unfolded planes at height `h_t` (Kumar Fig. 3), so the last anchor
/// of a robot is where that line crosses the top edge of its plane.
struct KumarChain {
    lengths: [f64; 2],
    anchor_x: f64,
    anchor_behind: f64,
    tether_height: f64,
    limit: f64,
}

impl AnchorSource for KumarChain {
    fn tether_at(&self, plane: usize, p: &Point2<f64>) -> Option<TetherSpec> {
        let top = *self.lengths.get(plane)?;
        let above: f64 = self.lengths[..plane].iter().sum::<f64>() + self.anchor_behind;
        let anchor_y = top + above;
        let x_edge = p.x + (self.anchor_x - p.x) * (top - p.y) / (anchor_y - p.y);
        Some(TetherSpec {
            anchor: Point3::new(x_edge, top, self.tether_height),
            max_tension: Some(self.limit),
        })
    }
}

fn kumar_sweep() -> Result<Vec<Case>, String> {
    let rover = FourWheelRover::default();
    let mu = 0.4;
    let planes = [
        MapPlane {
            plane: SlopePlane::new(55f64.to_radians(), mu).map_err(|e| e.to_string())?,
            x_range: [-8.0, 8.0],
            y_range: [0.0, 7.0],
        },
        MapPlane {
            plane: SlopePlane::new(65f64.to_radians(), mu).map_err(|e| e.to_string())?,
            x_range: [-8.0, 8.0],
            y_range: [0.0, 7.0],
        },
    ];
    let grid = GridSpec::new(1.0, Heading::AwayFromAnchor).map_err(|e| e.to_string())?;
    let lp = TensionLimitedLp::default();
    let mut maps: Vec<Vec<PoseVerdict>> = Vec::new();
    for limit in [200.0, 300.0, 500.0] {
        let chain = KumarChain {
            lengths: [8.0, 8.0],
            anchor_x: 4.0,
            anchor_behind: 3.0,
            tether_height: rover.params().tether_exit.z,
            limit,
        };
        maps.push(stability_map(&rover, &lp, &planes, &chain, &grid).map_err(|e| e.to_string())?);
    }
    let failed = maps
        .iter()
        .flatten()
        .filter(|v| {
            matches!(
                v.outcome,
                rappel::mechanics::stability_map::PoseOutcome::Failed { .. }
            )
        })
        .count();
    let count = |m: &[PoseVerdict], plane: usize| {
        m.iter()
            .filter(|v| v.plane == plane && v.is_stable())
            .count()
    };
    let total = maps[0].len();
    let w = rover.params().mass * STANDARD_GRAVITY;
    // Least tension holding the robot with the tether straight up the fall line, parallel to the slope.
    let least = |deg: f64| w * (deg.to_radians().sin() - mu * deg.to_radians().cos());
    let chain200 = KumarChain {
        lengths: [8.0, 8.0],
        anchor_x: 4.0,
        anchor_behind: 3.0,
        tether_height: rover.params().tether_exit.z,
        limit: 200.0,
    };
    let inscribed = TensionLimitedLp::default().with_pyramid(FrictionPyramid::Inscribed);
    let map200_in =
        stability_map(&rover, &inscribed, &planes, &chain200, &grid).map_err(|e| e.to_string())?;
    let stable200_in = count(&map200_in, 0) + count(&map200_in, 1);
    // Kumar Fig. 5 itself (200 / 300 / 500 N from tracked windings, with the paper's verdicts and
    // the known differences) is the `tracking` suite.
    let mut cases = vec![
        Case::property(
            SUITE,
            "Kumar sweep: poses that could not be assessed",
            failed.to_string(),
            "0",
            failed == 0,
        ),
        Case::closed_form(
            SUITE,
            format!(
                "Kumar sweep, T2max 200 N, pyramid inscribed in the cone: stable poses of {total}"
            ),
            stable200_in.to_string(),
            format!("0 (exact cone needs >= {:.1} N on 55 deg)", least(55.0)),
            stable200_in == 0,
        ),
        Case::paper_verdict(
            SUITE,
            "Kumar sweep, T2max 500 N: stable poses on the 65 deg slope",
            count(&maps[2], 1).to_string(),
            "> 0 (Kumar Fig. 5c)",
            count(&maps[2], 1) > 0,
        ),
    ];
    // The pose straight below the anchor on the 65° slope needs the closed-form least tension.
    let chain = KumarChain {
        lengths: [8.0, 8.0],
        anchor_x: 4.0,
        anchor_behind: 3.0,
        tether_height: rover.params().tether_exit.z,
        limit: 500.0,
    };
    let position = Point2::new(4.0, 2.0);
    let tether = chain.tether_at(1, &position);
    let placed = place(
        &rover,
        &PlanarPose::new(4.0, 2.0, PI),
        &planes[1].plane,
        tether.as_ref(),
    )
    .map_err(|e| e.to_string())?;
    let required = lp
        .check(&placed)
        .map_err(|e| e.to_string())?
        .required_tension
        .unwrap_or(f64::NAN);
    cases.push(Case::closed_form(
        SUITE,
        "Kumar LP, 65 deg, tether up the fall line: least tension",
        format!("{required:.4} N"),
        format!(
            "{:.4} N = m g (sin eta - mu cos eta), rel. 1e-6",
            least(65.0)
        ),
        ((required - least(65.0)) / least(65.0)).abs() <= 1e-6,
    ));
    Ok(cases)
}

/// Axel QP sanity (issue 5 item 8) and eq. 3.32 against the QP.
fn axel_qp() -> Result<Vec<Case>, String> {
    let qp = StabilityQp::default();
    let axel = Axel::default();
    let mu = 0.8;
    let downhill = PlanarPose::new(0.0, 0.0, PI);
    let up_fall_line = TetherSpec {
        anchor: Point3::new(0.0, 30.0, 0.0),
        max_tension: None,
    };
    let check = |deg: f64, tether: Option<&TetherSpec>| -> Result<(bool, f64), String> {
        let plane = SlopePlane::new(f64::to_radians(deg), mu).map_err(|e| e.to_string())?;
        let placed = place(&axel, &downhill, &plane, tether).map_err(|e| e.to_string())?;
        let r = qp.check(&placed).map_err(|e| e.to_string())?;
        Ok((r.stable, r.margin))
    };
    let word = |b: bool| if b { "stable" } else { "unstable" };
    let flat = check(0.0, None)?.0;
    let bare = check(55.0, None)?.0;
    let held = check(55.0, Some(&up_fall_line))?.0;
    let margins = (1..=6)
        .map(|k| {
            check(10.0 * k as f64, Some(&up_fall_line)).map(|r| if r.0 { r.1 } else { f64::NAN })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let decreasing = margins.windows(2).all(|w| w[1] < w[0]);
    let mut cases = vec![
        Case::closed_form(
            SUITE,
            "Axel QP, flat ground, no tether",
            word(flat),
            "stable",
            flat,
        ),
        Case::closed_form(
            SUITE,
            "Axel QP, 55 deg, mu 0.8, no tether",
            word(bare),
            "unstable (tan 55 deg = 1.43 > mu)",
            !bare,
        ),
        Case::property(
            SUITE,
            "Axel QP, 55 deg, mu 0.8, tether up the fall line",
            word(held),
            "stable",
            held,
        ),
        Case::property(
            SUITE,
            "Axel QP margin, tethered (inline boom), slopes 10..60 deg step 10",
            margins
                .iter()
                .map(|m| format!("{m:.2}"))
                .collect::<Vec<_>>()
                .join(" "),
            "strictly decreasing",
            decreasing,
        ),
    ];
    // Eq. 3.32: all mass at the axle, point contacts, fixed boom: the QP's tension is fixed by the
    // moment balance about the wheel contact line.
    let params = AxelParams {
        boom_mass: 0.0,
        body_mass: 55.0,
        moment_coefficient: 0.0,
        boom: BoomMode::Fixed(30f64.to_radians()),
        ..AxelParams::default()
    };
    let light = Axel::new(params).map_err(|e| e.to_string())?;
    let eta = 40f64.to_radians();
    let plane = SlopePlane::new(eta, 1.0).map_err(|e| e.to_string())?;
    let placed =
        place(&light, &downhill, &plane, Some(&up_fall_line)).map_err(|e| e.to_string())?;
    let t_qp = qp
        .check(&placed)
        .map_err(|e| e.to_string())?
        .tether_tension
        .unwrap_or(f64::NAN);
    let dir = placed
        .tether
        .map(|t| t.direction.into_inner())
        .unwrap_or_else(Vector3::zeros);
    let tether_angle = dir.dot(&plane.normal()).asin();
    let estimate = tether_tension_estimate(
        55.0,
        STANDARD_GRAVITY,
        params.wheel_radius,
        params.boom_length,
        eta,
        30f64.to_radians(),
        tether_angle,
    )
    .unwrap_or(f64::NAN);
    cases.push(Case::closed_form(
        SUITE,
        "Axel eq. 3.32 (re-derived) vs QP tether tension, 40 deg, boom 30 deg",
        format!("{t_qp:.3} N"),
        format!("{estimate:.3} N (rel. 1e-5)"),
        ((t_qp - estimate) / estimate).abs() <= 1e-5,
    ));
    Ok(cases)
}

/// Every mechanics regression case.
pub fn suite() -> Result<Vec<Case>, String> {
    let mut cases = capstan()?;
    cases.extend(helix()?);
    cases.extend(heavy_rope_on_tilted_plane()?);
    cases.extend(two_slopes()?);
    cases.extend(kumar_sweep()?);
    cases.extend(axel_qp()?);
    cases.extend(wheeled_tether_cone());
    Ok(cases)
}

/// The tether cone a rigid four-wheel rover's stability QP allows, against the thesis' point-robot
/// cone (eq. 2.7): facing away from the anchor with an unlimited tether, the wheels need only
/// cancel the cross-tether component of gravity, `m g sin(eta) sin(theta) <= mu m g cos(eta)`, so
/// without tipping the two must agree to the bisection tolerance.
fn wheeled_tether_cone() -> Vec<Case> {
    use rappel::mechanics::anchor_traversability::{AnchorTraversability, TetherLimit};
    use rappel::mechanics::traversability::StabilitySettings;
    use rappel::mechanics::wheeled_tether_cone::{ANGLE_TOLERANCE, WheeledTetherCone};
    let rover = FourWheelRover::default();
    let qp = StabilityQp::new(StabilitySettings::default());
    let model = WheeledTetherCone::new(&rover, &qp);
    let mut cases = Vec::new();
    for (deg, mu) in [(35.0, 0.4), (45.0, 0.4), (55.0, 0.6), (65.0, 0.4)] {
        let eta: f64 = f64::to_radians(deg);
        let expected = (mu / eta.tan()).asin();
        let name = format!("four-wheel QP tether cone, {deg} deg, mu {mu}");
        let (measured, pass) =
            match SlopePlane::new(eta, mu).map(|plane| model.tether_limit(&plane)) {
                Ok(TetherLimit::Cone { max_angle }) => (
                    format!("{:.3} deg", max_angle.to_degrees()),
                    (max_angle - expected).abs() <= 2.0 * ANGLE_TOLERANCE,
                ),
                Ok(TetherLimit::TetherFree) => ("tether-free".to_string(), false),
                Err(e) => (e.to_string(), false),
            };
        cases.push(Case::closed_form(
            SUITE,
            name,
            measured,
            format!(
                "{:.3} deg = asin(mu cot eta), eq. 2.7",
                expected.to_degrees()
            ),
            pass,
        ));
    }
    cases
}
