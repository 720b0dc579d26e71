//! A profile's cumulative radial integrals per C column, exact for its
//! piecewise-linear interpolant: what the polar near-field rule
//! ([`crate::polar`]) sums along each ray from the foot point.

/// Cumulative radial integrals of a profile per C column and hemisphere,
/// at the γ nodes: θ is the angle from the opening's axis on the side the
/// receiver is (θ = γ in front, θ = 180° − γ behind), and
/// `sec[c][j] = ∫₀^θⱼ I (sec θ − cos θ) dθ`, `sin[c][j] = ∫₀^θⱼ I sin θ dθ`,
/// stored at the grid's own index of θⱼ (front half up to 89.5°, back
/// half from 180° down to 90.5°; the 90° node is never a lower cell bound
/// and holds 0).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RadialTables {
    pub sec: Vec<f64>,
    pub sin: Vec<f64>,
    /// Per hemisphere angle node θⱼ (j below 90°): sin θⱼ, cos θⱼ,
    /// u = asinh tan θⱼ and e^−u, so that a ray end costs no trigonometry
    /// of its cell's bound.
    pub node_sin: Vec<f64>,
    pub node_cos: Vec<f64>,
    pub node_u: Vec<f64>,
    pub node_exp: Vec<f64>,
    /// atan(e^−u) at the node and its derivative in u: the renderer's
    /// angular moment over a short cell without an arctangent.
    pub node_moment: Vec<f64>,
    pub node_moment_slope: Vec<f64>,
}

/// The grid index of hemisphere angle node j.
pub(crate) fn node_index(gamma_count: usize, front: bool, j: usize) -> usize {
    if front { j } else { gamma_count - 1 - j }
}

/// Where the cells' angular moment switches from quadrature to the
/// series of the inverse tangent integral (u₀ ≥ 2 is θ ≥ 74.6°, where
/// e^−u ≤ 0.135 and four terms are exact to 1e-10).
pub(crate) const SERIES_FROM_U: f64 = 2.0;

/// Ti₂(y) = ∫₀^y atan(t)/t dt for 0 ≤ y ≤ 0.14, its Maclaurin series.
pub(crate) fn inverse_tangent_integral(y: f64) -> f64 {
    let y2 = y * y;
    y * (1.0 - y2 * (1.0 / 9.0 - y2 * (1.0 / 25.0 - y2 * (1.0 / 49.0 - y2 / 81.0))))
}

/// ∫ atan(e^−v) dv over [u₀, u]: the angular moment of a cell, since
/// π/2 − θ = 2 atan(e^−u) for u = asinh(tan θ). Towards 90° the cell
/// spans ever more u (to infinity) and the series is exact there; below
/// it a cell spans little u and `nodes` Gauss–Legendre points suffice.
pub(crate) fn angular_moment(u0: f64, u: f64, exact: bool) -> f64 {
    if u0 >= SERIES_FROM_U {
        return inverse_tangent_integral((-u0).exp()) - inverse_tangent_integral((-u).exp());
    }
    let f = |v: f64| (-v).exp().atan();
    if !exact {
        return f(0.5 * (u0 + u)) * (u - u0);
    }
    let pieces = ((u - u0) / 0.25).ceil().max(1.0) as usize;
    let step = (u - u0) / pieces as f64;
    let mut sum = 0.0;
    for p in 0..pieces {
        let a = u0 + p as f64 * step;
        for (x, w) in GAUSS8 {
            sum += w * f(a + x * step);
        }
    }
    sum * step
}

/// Gauss–Legendre nodes on [0, 1] and weights, 8 points.
const GAUSS8: [(f64, f64); 8] = [
    (0.019_855_071_751_231_8, 0.050_614_268_145_188_1),
    (0.101_666_761_293_186_6, 0.111_190_517_226_687_2),
    (0.237_233_795_041_835_5, 0.156_853_322_938_943_6),
    (0.408_282_678_752_175, 0.181_341_891_689_181),
    (0.591_717_321_247_825, 0.181_341_891_689_181),
    (0.762_766_204_958_164_5, 0.156_853_322_938_943_6),
    (0.898_333_238_706_813_4, 0.111_190_517_226_687_2),
    (0.980_144_928_248_768_2, 0.050_614_268_145_188_1),
];

/// How the last, partial γ cell of a radial integral is taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Partial {
    /// Gauss–Legendre in u to rounding: the reference.
    Exact,
    /// The angular moment by the midpoint in u below 74.6° (where a cell
    /// spans at most 0.03 of u): the renderer.
    Fast,
}

/// The two radial integrals of one column of a linear piece I₀ + m (θ − θ₀)
/// from θ₀ to θ (u = asinh tan θ, `u0` at θ₀): (sec − cos kernel, sin kernel).
/// The sec part is written about the piece's value at 90°,
/// ∫ (I₉₀ − m (π/2 − θ)) sec θ dθ = I₉₀ (u − u₀) − 2 m ∫ atan(e^−v) dv,
/// which does not cancel where the profile falls to 0 at 90°.
fn partial_cell(
    theta0: f64,
    theta: f64,
    u0: f64,
    u: f64,
    i0: f64,
    m: f64,
    how: Partial,
) -> (f64, f64) {
    let (s0, c0) = theta0.sin_cos();
    let (s1, c1) = theta.sin_cos();
    let dt = theta - theta0;
    let sin_kernel = i0 * (c0 - c1) + m * (s1 - s0 - dt * c1);
    let cos_kernel = i0 * (s1 - s0) + m * (dt * s1 + c1 - c0);
    let at_axis = i0 + m * (std::f64::consts::FRAC_PI_2 - theta0);
    let moment = angular_moment(u0, u, how == Partial::Exact);
    (
        at_axis * (u - u0) - 2.0 * m * moment - cos_kernel,
        sin_kernel,
    )
}

impl RadialTables {
    /// The tables of a profile grid (`candela` per C column of
    /// `gamma_count` values, C-major) whose γ step divides 90°.
    pub fn new(
        c_count: usize,
        gamma_count: usize,
        gamma_step_deg: f64,
        candela: &[f32],
    ) -> RadialTables {
        let gc = gamma_count;
        let half = ((gc - 1) / 2).max(1);
        let step = gamma_step_deg.to_radians();
        let mut sec = vec![0.0; c_count * gc];
        let mut sin = vec![0.0; c_count * gc];
        for c in 0..c_count {
            let at = |i: usize| candela[c * gc + i] as f64;
            for front in [true, false] {
                let (mut s, mut k) = (0.0, 0.0);
                for j in 0..half {
                    let i = node_index(gc, front, j);
                    sec[c * gc + i] = s;
                    sin[c * gc + i] = k;
                    if j + 1 == half {
                        break; // the cell up to 90° is only ever partial
                    }
                    let (t0, t1) = (j as f64 * step, (j + 1) as f64 * step);
                    let i0 = at(i);
                    let m = (at(node_index(gc, front, j + 1)) - i0) / step;
                    let (u0, u1) = (t0.tan().asinh(), t1.tan().asinh());
                    let (ds, dk) = partial_cell(t0, t1, u0, u1, i0, m, Partial::Exact);
                    s += ds;
                    k += dk;
                }
            }
        }
        let nodes = (0..half).map(|j| j as f64 * step);
        let node_u: Vec<f64> = nodes.clone().map(|t| t.tan().asinh()).collect();
        RadialTables {
            sec,
            sin,
            node_sin: nodes.clone().map(f64::sin).collect(),
            node_cos: nodes.map(f64::cos).collect(),
            node_exp: node_u.iter().map(|u| (-u).exp()).collect(),
            node_moment: node_u.iter().map(|u| (-u).exp().atan()).collect(),
            node_moment_slope: node_u
                .iter()
                .map(|u| -(-u).exp() / (1.0 + (-2.0 * u).exp()))
                .collect(),
            node_u,
        }
    }
}
