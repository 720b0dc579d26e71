//! The automatic γ grid: listed angles, fine where the distribution bends
//! and coarse where it does not, as real photometric files list theirs
//! (a road luminaire's 44 angles over 0–140°), instead of one fine step
//! everywhere (a 4.5° spot once took 1 153 angles at 0.156°).
//!
//! The angles lie on a lattice of 5°/64 from a 5° start. An interval is
//! halved where the map's mean over the cell its midpoint would own
//! differs from the table's linear interpolation there by more than a
//! tolerance relative to the local intensity (with the sphere's mean
//! intensity as a floor), and by more than three standard deviations of
//! that cell's photon noise: a grid never chases noise, nor goes finer
//! than an eighth of a texel. Tolerances are tried coarse to fine; the
//! grid is the first that holds every [`FidelityTargets`] figure against
//! the map, within [`MAX_AUTOMATIC_GAMMAS`] angles.

use crate::cubemap::CubeMapLayout;
use crate::fidelity::{AngleNoise, BeamFigures, FidelityTargets, Miss, TableFidelity};
pub use crate::noise::PhotonNoise;
use crate::resample::CellFlux;
use crate::table::CandelaTable;

/// The lattice the automatic grid's angles lie on (degrees). The fine
/// binning's band edges are at half of it, so the cell edge midway
/// between any two lattice angles is a band edge.
pub const LATTICE_STEP_DEG: f64 = 5.0 / 64.0;
/// Lattice steps from γ 0° to 180°.
const LATTICE_STEPS: u32 = 2304;
/// Lattice steps in the coarsest interval (5°).
const COARSEST_STEPS: u32 = 64;
/// The most γ angles an automatic grid lists: one per half degree, as the
/// finest files in the wild, which every reader takes.
pub const MAX_AUTOMATIC_GAMMAS: usize = 361;
/// Tolerances on the interpolation error, relative to the local intensity
/// (floored at the sphere's mean intensity), coarsest first.
const TOLERANCES: [f64; 10] = [
    0.05, 0.02, 0.01, 0.005, 0.002, 0.001, 5e-4, 2e-4, 1e-4, 5e-5,
];
/// Rounds of halving the intervals that decide a missed figure, at most.
const TARGETED_ROUNDS: usize = 6;
/// Standard deviations of a cell's photon noise a deviation must exceed
/// before it is taken for the distribution's shape.
const NOISE_Z: f64 = 3.0;

/// The band edges (degrees) of the fine binning the automatic grid is
/// chosen on: every half lattice step from 0° to 180°.
pub fn band_edges_deg() -> Vec<f64> {
    (0..=2 * LATTICE_STEPS)
        .map(|k| f64::from(k) * 180.0 / f64::from(2 * LATTICE_STEPS))
        .collect()
}

/// Prefix sums of a [`CellFlux`]'s bands per C-plane, for the mean over
/// any run of bands in O(1).
struct BandPrefix {
    bands: usize,
    planes: usize,
    flux: Vec<f64>,
    omega: Vec<f64>,
}

impl BandPrefix {
    fn new(cells: &CellFlux) -> Self {
        let (flux, omega) = cells.band_values();
        let planes = cells.c_planes_deg().len();
        let bands = flux.len() / planes;
        let prefix = |v: &[f64]| {
            let mut out = Vec::with_capacity(planes * (bands + 1));
            for plane in v.chunks_exact(bands) {
                let mut sum = 0.0;
                out.push(0.0);
                for x in plane {
                    sum += x;
                    out.push(sum);
                }
            }
            out
        };
        BandPrefix {
            bands,
            planes,
            flux: prefix(flux),
            omega: prefix(omega),
        }
    }

    /// The table on the lattice angles `grid` (lattice steps), as
    /// [`CellFlux::table`] makes it (polar caps shared by every plane, a
    /// cell without solid angle taking its texel's value), in O(cells).
    fn table(&self, cells: &CellFlux, grid: &[u32]) -> CandelaTable {
        let n = grid.len();
        let c_planes = cells.c_planes_deg();
        let gammas = degrees(grid);
        let edges = |j: usize| -> (usize, usize) {
            let lo = if j == 0 {
                2 * grid[0]
            } else {
                grid[j - 1] + grid[j]
            };
            let hi = if j + 1 == n {
                2 * grid[n - 1]
            } else {
                grid[j] + grid[j + 1]
            };
            (lo as usize, hi as usize)
        };
        let cap = |j: usize| -> (f64, f64) {
            let (b0, b1) = edges(j);
            (0..self.planes).fold((0.0, 0.0), |(f, o), p| {
                let (df, dom) = self.cell(p, b0, b1);
                (f + df, o + dom)
            })
        };
        let pole = |j: usize| grid[j] == 0 || grid[j] == LATTICE_STEPS;
        let caps = [cap(0), cap(n - 1)];
        let mut candela = Vec::with_capacity(self.planes * n);
        for (i, &c) in c_planes.iter().enumerate() {
            for j in 0..n {
                let (flux, omega) = if pole(j) {
                    caps[usize::from(j != 0)]
                } else {
                    let (b0, b1) = edges(j);
                    self.cell(i, b0, b1)
                };
                candela.push(
                    if omega > 0.0 {
                        flux / omega
                    } else {
                        cells.point(c, gammas[j])
                    }
                    .max(0.0),
                );
            }
        }
        CandelaTable {
            c_planes_deg: c_planes.to_vec(),
            gammas_deg: gammas,
            candela,
        }
    }

    /// Flux (lm) and solid angle (sr) of `plane` between band edges `b0`
    /// and `b1`.
    fn cell(&self, plane: usize, b0: usize, b1: usize) -> (f64, f64) {
        let row = plane * (self.bands + 1);
        (
            self.flux[row + b1] - self.flux[row + b0],
            self.omega[row + b1] - self.omega[row + b0],
        )
    }
}

/// The table of `cells` on the automatic grid and how faithfully it
/// carries the map whose figures are `map`.
pub(crate) fn automatic(
    cells: &CellFlux,
    layout: CubeMapLayout,
    map: BeamFigures,
    targets: FidelityTargets,
    noise: Option<PhotonNoise>,
    (peak_noise, angle_noise): (f64, AngleNoise),
) -> (CandelaTable, TableFidelity) {
    let prefix = BandPrefix::new(cells);
    // Steps finer than an eighth of a texel resolve nothing more of the
    // map's reconstruction (linear between texel centres); a beam two
    // texels wide needs that eighth to keep its flux.
    let texel_deg = 90.0 / f64::from(layout.resolution);
    let mut finest_steps = COARSEST_STEPS;
    while finest_steps > 1 && f64::from(finest_steps / 2) * LATTICE_STEP_DEG >= texel_deg / 8.0 {
        finest_steps /= 2;
    }
    let mean_cd = map.flux_lm.max(0.0) / (4.0 * std::f64::consts::PI);
    let grid: Vec<u32> = (0..=LATTICE_STEPS)
        .step_by(COARSEST_STEPS as usize)
        .collect();
    // What the finest grid itself misses of the map is no coarser grid's
    // fault (its C-planes average across C, a line through the map does
    // not): the angle and peak targets are held on top of it.
    let finest: Vec<u32> = (0..=LATTICE_STEPS).step_by(finest_steps as usize).collect();
    // Built only when a grid misses a figure.
    let finest_table = std::cell::OnceCell::new();
    let finest_of = || finest_table.get_or_init(|| prefix.table(cells, &finest));
    let finest_figures = std::cell::OnceCell::new();
    let judge = |grid: &[u32]| {
        let table = prefix.table(cells, grid);
        let mut fidelity = TableFidelity::new(true, map, &table, targets, peak_noise, angle_noise);
        if !fidelity.holds() {
            let f = *finest_figures.get_or_init(|| BeamFigures::of_table(finest_of()));
            fidelity = fidelity.with_finest(f);
        }
        (table, fidelity)
    };
    // The coarsest tolerance whose grid holds the figures, by bisection
    // over the tolerances (a finer tolerance refines a superset of
    // intervals); each grid is refined from the 5° start.
    let grid_at = |k: usize| {
        let mut g = grid.clone();
        let full = refine(
            &mut g,
            cells,
            &prefix,
            TOLERANCES[k],
            mean_cd,
            finest_steps,
            noise,
        );
        (g, full)
    };
    let last = TOLERANCES.len() - 1;
    let (g, full_last) = grid_at(last);
    let (t, f) = judge(&g);
    let mut best = (g, full_last, t, f);
    if best.3.holds() || best.1 {
        // Search coarser: the first (coarsest) tolerance that still holds
        // and is within the budget.
        let (mut lo, mut hi) = (0usize, last);
        while lo < hi {
            let mid = (lo + hi) / 2;
            let (g, full) = grid_at(mid);
            let (t, f) = judge(&g);
            if f.holds() || (full && !best.3.holds()) {
                best = (g, full, t, f);
                hi = mid;
            } else {
                lo = mid + 1;
            }
        }
    }
    let (mut grid, mut full, mut table, mut fidelity) = best;
    // What the local test let through (a cone's flux sums many cells,
    // each within its noise; a beam angle moves with the peak): the
    // intervals where a missed figure is decided, halved until it holds.
    for _ in 0..TARGETED_ROUNDS {
        if full {
            break;
        }
        let misses = fidelity.misses();
        if misses.is_empty() {
            break;
        }
        let chosen = intervals_deciding(&grid, &table, finest_of(), &prefix, &misses, finest_steps);

        if chosen.is_empty() {
            break;
        }
        let room = MAX_AUTOMATIC_GAMMAS.saturating_sub(grid.len());
        full = chosen.len() > room;
        let mut halved: Vec<u32> = chosen
            .iter()
            .take(room)
            .map(|&j| (grid[j] + grid[j + 1]) / 2)
            .collect();
        grid.append(&mut halved);
        grid.sort_unstable();
        (table, fidelity) = judge(&grid);
    }
    (table, fidelity)
}

/// The intervals of `grid` (by their first angle's index) where the
/// missed figures are decided, that can still be halved: every interval
/// below a missed cone's edge, around the table's crossings of a missed
/// angle's level in its plane, beside its peak; all of them for the
/// total flux.
fn intervals_deciding(
    grid: &[u32],
    table: &CandelaTable,
    finest: &CandelaTable,
    prefix: &BandPrefix,
    misses: &[Miss],
    finest_steps: u32,
) -> Vec<usize> {
    let n = grid.len();
    let gammas = degrees(grid);
    let mut chosen = vec![false; n - 1];
    let mut mark = |j: usize| {
        if j + 1 < n {
            chosen[j] = true;
        }
    };
    for miss in misses {
        match *miss {
            Miss::Flux { .. } => {
                // The quarter of the intervals whose midpoints the table
                // misses by the most lumens.
                let ng = n;
                let mut errors: Vec<(f64, usize)> = (0..n - 1)
                    .filter(|&j| grid[j + 1] - grid[j] >= 2 * finest_steps)
                    .map(|j| {
                        let m = (grid[j] + grid[j + 1]) / 2;
                        let lumens: f64 = (0..prefix.planes)
                            .map(|plane| {
                                let (flux, omega) = prefix.cell(
                                    plane,
                                    (grid[j] + m) as usize,
                                    (m + grid[j + 1]) as usize,
                                );
                                let lerp = 0.5
                                    * (table.candela[plane * ng + j]
                                        + table.candela[plane * ng + j + 1]);
                                (flux - lerp * omega).abs()
                            })
                            .sum();
                        (lumens, j)
                    })
                    .collect();
                errors.sort_by(|a, b| b.0.total_cmp(&a.0));
                for &(_, j) in errors.iter().take(errors.len().div_ceil(4)) {
                    mark(j);
                }
            }
            Miss::Cone { half_angle_deg, .. } => {
                for j in 0..n - 1 {
                    if gammas[j] < half_angle_deg {
                        mark(j);
                    }
                }
            }
            Miss::Angle { field, plane, .. } => {
                // An angle is a crossing of a fraction of its plane's
                // maximum: where the crossings are, and where the maximum
                // is or the table misses a higher one.
                let fraction = if field { 0.1 } else { 0.5 };
                let c0 = if plane == 0 { 0.0 } else { 90.0 };
                for c in [c0, c0 + 180.0] {
                    let values: Vec<f64> = gammas.iter().map(|&g| table.intensity(c, g)).collect();
                    let (top, highest) =
                        values.iter().enumerate().fold((0, 0.0), |(k, v), (i, &x)| {
                            if x > v { (i, x) } else { (k, v) }
                        });
                    let level = fraction * highest;
                    (top.saturating_sub(1)..=top).for_each(&mut mark);
                    // A higher maximum, or a crossing of the level, that
                    // an interval's interpolation hides from the finest
                    // grid's values inside it.
                    let mut k = 0;
                    for j in 0..n - 1 {
                        if (values[j] - level) * (values[j + 1] - level) <= 0.0 {
                            (j.saturating_sub(1)..=j + 1).for_each(&mut mark);
                        }
                        while k < finest.gammas_deg.len() && finest.gammas_deg[k] < gammas[j + 1] {
                            let g = finest.gammas_deg[k];
                            k += 1;
                            if g <= gammas[j] {
                                continue;
                            }
                            let t = (g - gammas[j]) / (gammas[j + 1] - gammas[j]);
                            let lerp = values[j] + t * (values[j + 1] - values[j]);
                            let fine = finest.intensity(c, g);
                            if fine > highest || (fine - level) * (lerp - level) < 0.0 {
                                mark(j);
                            }
                        }
                    }
                }
            }
            Miss::Peak { .. } => {
                let (_, _, peak_gamma) = table.peak();
                let k = gammas.partition_point(|&g| g < peak_gamma - 1e-9);
                (k.saturating_sub(2)..=k + 1).for_each(&mut mark);
            }
        }
    }
    (0..n - 1)
        .filter(|&j| chosen[j] && grid[j + 1] - grid[j] >= 2 * finest_steps)
        .collect()
}

fn degrees(grid: &[u32]) -> Vec<f64> {
    grid.iter()
        .map(|&u| f64::from(u) * LATTICE_STEP_DEG)
        .collect()
}

/// Halves the intervals of `grid` whose midpoints the table misses by
/// more than `tolerance`, round after round, until none does; true when
/// the angle budget ran out first (the worst intervals halved last).
fn refine(
    grid: &mut Vec<u32>,
    cells: &CellFlux,
    prefix: &BandPrefix,
    tolerance: f64,
    mean_cd: f64,
    finest_steps: u32,
    noise: Option<PhotonNoise>,
) -> bool {
    loop {
        let table = prefix.table(cells, grid);
        let ng = grid.len();
        let value = |plane: usize, j: usize| table.candela[plane * ng + j];
        // (excess over the tolerance, interval index) of every interval
        // to halve.
        let mut splits: Vec<(f64, usize)> = Vec::new();
        for j in 0..ng - 1 {
            let (a, b) = (grid[j], grid[j + 1]);
            if b - a < 2 * finest_steps {
                continue;
            }
            let m = (a + b) / 2;
            // The cell the midpoint would own, in band edges (half steps).
            let (b0, b1) = ((a + m) as usize, (m + b) as usize);
            let mut worst: f64 = 0.0;
            let mut judge = |flux: f64, omega: f64, lerp: f64| {
                if !(omega > 0.0) {
                    return;
                }
                let mid = flux / omega;
                let sigma = noise.map_or(0.0, |n| n.sigma_cd(flux, omega));
                let deviation = (mid - lerp).abs() - NOISE_Z * sigma;
                let allowed = tolerance * (mean_cd + mid.max(lerp));
                if allowed > 0.0 {
                    worst = worst.max(deviation / allowed);
                }
            };
            // Each plane, and their mean over the circle: a shape all
            // planes share shows there above the noise of any one plane.
            let (mut all_flux, mut all_omega, mut all_lerp) = (0.0, 0.0, 0.0);
            for plane in 0..prefix.planes {
                let (flux, omega) = prefix.cell(plane, b0, b1);
                let lerp = 0.5 * (value(plane, j) + value(plane, j + 1));
                judge(flux, omega, lerp);
                all_flux += flux;
                all_omega += omega;
                all_lerp += lerp * omega;
            }
            if all_omega > 0.0 {
                judge(all_flux, all_omega, all_lerp / all_omega);
            }
            if worst > 1.0 {
                splits.push((worst, j));
            }
        }
        if splits.is_empty() {
            return false;
        }
        let room = MAX_AUTOMATIC_GAMMAS.saturating_sub(ng);
        let full = splits.len() > room;
        if full {
            splits.sort_by(|x, y| y.0.total_cmp(&x.0));
            splits.truncate(room);
        }
        let mut halved: Vec<u32> = splits
            .iter()
            .map(|&(_, j)| (grid[j] + grid[j + 1]) / 2)
            .collect();
        grid.append(&mut halved);
        grid.sort_unstable();
        if full {
            return true;
        }
    }
}
