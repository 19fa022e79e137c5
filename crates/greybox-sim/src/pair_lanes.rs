//! The pair terms of the force pass (solver step 3a) and the kinematics pass (step 6),
//! computed [`LANES`] pairs at a time so that the compiler turns them into vector
//! instructions: AVX-512 (one register of eight doubles), AVX2 (two of four) or the x86-64
//! baseline (SSE2), whichever [`crate::cpu`] picks at run time.
//!
//! **Same bits on every path.** The force pass takes a row's pairs in groups of [`LANES`]:
//! pair k of the row goes to lane k mod [`LANES`], each lane keeps its own partial sum, and the lanes are added in one fixed tree
//! ([`sum_lanes`]). Each lane's arithmetic is the same IEEE operations in the same order on
//! every path (Rust never contracts a·b + c into a fused multiply–add, and the viscosity's
//! "approaching pairs only" is a select, not `min`, whose result for ±0 is unspecified), so
//! the baseline, AVX2 and AVX-512 builds give identical bits
//! (`crates/greybox-sim/tests/simd_paths.rs` runs a cut on each and compares the bytes).
//! The padding lanes of a row's last group repeat the particle itself (zero distance) and
//! are masked out of the sums and never stored.
//!
//! The layout is structure-of-arrays in registers: each group first gathers the partners'
//! fields into one array per field (`gather!`), then runs the arithmetic over the arrays.
//! The kinematics pass stays one pair at a time (see [`kinematics_row`]).

use crate::cpu::multiversion;
use crate::kernel::PairTable;
use crate::neighbours::NeighbourList;
use crate::rates::Rates;

/// Pairs computed together; the lane sums are added by [`sum_lanes`]'s fixed tree.
pub(crate) const LANES: usize = 8;
type Lanes = [f64; LANES];

/// Per-particle data packed for the gather: one record of exactly two cache lines, the
/// fields of the kinematics pass in the first.
#[derive(Debug, Clone, Copy, Default)]
#[repr(C, align(64))]
pub(crate) struct Packed {
    pub x: f64,
    pub y: f64,
    pub vx: f64,
    pub vy: f64,
    /// m/ρ.
    pub vol: f64,
    /// 1/ρ.
    pub inv_rho: f64,
    /// Mass (mass scaling included), kg/m; read only by the refined passes.
    pub m: f64,
    /// Smoothing length, m; read only by the refined passes.
    pub h: f64,
    /// σ/ρ² (total stress, pressure included).
    pub txx: f64,
    pub txy: f64,
    pub tyy: f64,
    /// Artificial stress R (already /ρ²).
    pub rxx: f64,
    pub rxy: f64,
    pub ryy: f64,
    pub temp: f64,
    /// Conductivity, W/(m·K).
    pub k: f64,
}

/// Constants of the force pass.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ForceConstants {
    /// Particle mass (mass scaling included), kg/m, of a uniform model (a refined one reads
    /// [`Packed::m`]).
    pub mass: f64,
    /// Monaghan viscosity coefficients α, β.
    pub alpha: f64,
    pub beta: f64,
    /// Longitudinal wave speed, m/s.
    pub c_long: f64,
    /// 1/W(Δx) for the artificial-stress factor f = W(r)/W(Δx) (a refined model: of the
    /// unit kernel, h = 1 and Δx = 1/smoothing ratio, since f depends on r/h only).
    pub inv_w_dx: f64,
    /// 1 with artificial stress, 0 without.
    pub artificial_stress_on: f64,
}

/// One particle's sums over its own half-list row in the force pass.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ForceSums {
    /// Acceleration, m/s².
    pub ax: f64,
    pub ay: f64,
    /// Conduction sum ρ c dT/dt, W/m³.
    pub cond: f64,
    /// Viscous dissipation of the row's pairs, W/m.
    pub av_power: f64,
}

/// The lanes added in a fixed tree: ((0+1)+(2+3)) + ((4+5)+(6+7)).
#[inline(always)]
fn sum_lanes(l: &Lanes) -> f64 {
    ((l[0] + l[1]) + (l[2] + l[3])) + ((l[4] + l[5]) + (l[6] + l[7]))
}

/// `value` in the lanes below `n`, 0 in the padding.
#[inline(always)]
fn masked(l: usize, n: usize, value: f64) -> f64 {
    if l < n {
        value
    } else {
        0.0
    }
}

/// One field of the records `idx` as lanes.
macro_rules! gather {
    ($packed:expr, $idx:expr, $field:ident) => {{
        let lanes: Lanes = std::array::from_fn(|l| $packed[$idx[l]].$field);
        lanes
    }};
}

/// The pair functions [W, g, g_cond, h_visc] of [`PairTable::at`] for pairs of smoothing
/// lengths h_a and h_b at squared distances `r2`, from the table of the unit kernel (h = 1):
/// with h_ij = (h_a + h_b)/2 and q² = r²/h_ij², W = Ŵ(q²)/h², g = ĝ(q²)/h⁴,
/// g_cond = ĝ_c(q²)/h⁴, h_visc = ĥ(q²)/h (the 2D kernel's scaling). Also returns Ŵ(q²), the
/// unit kernel's value, for the artificial-stress factor.
#[inline(always)]
fn variable_rows(
    unit: &PairTable,
    h_a: f64,
    h_b: &Lanes,
    r2: &Lanes,
) -> ([[f64; 4]; LANES], Lanes) {
    let mut rows = [[0.0; 4]; LANES];
    let mut w_unit = [0.0; LANES];
    for l in 0..LANES {
        let inv_h = 2.0 / (h_a + h_b[l]);
        let inv_h2 = inv_h * inv_h;
        let [w, g, gc, hv] = unit.at(r2[l] * inv_h2);
        let inv_h4 = inv_h2 * inv_h2;
        rows[l] = [w * inv_h2, g * inv_h4, gc * inv_h4, hv * inv_h];
        w_unit[l] = w;
    }
    (rows, w_unit)
}

/// The pair functions of one group of lanes (partners `idx` of particle `a` at squared
/// distances `r2`): [W, g, g_cond, h_visc] per lane, the unit kernel's W (the
/// artificial-stress factor's) and the partners' masses; see [`force_row`] for `REFINED`.
#[inline(always)]
fn pair_rows<const REFINED: bool>(
    table: &PairTable,
    k: &ForceConstants,
    a: &Packed,
    packed: &[Packed],
    idx: &[usize; LANES],
    r2: &Lanes,
) -> ([[f64; 4]; LANES], Lanes, Lanes) {
    if REFINED {
        let (rows, w_unit) = variable_rows(table, a.h, &gather!(packed, idx, h), r2);
        (rows, w_unit, gather!(packed, idx, m))
    } else {
        let rows: [[f64; 4]; LANES] = std::array::from_fn(|l| table.at(r2[l]));
        (rows, std::array::from_fn(|l| rows[l][0]), [k.mass; LANES])
    }
}

/// Force pass over particle `i`'s own row: sums i's share and writes, per pair, the kernel
/// values [W, g] to `wg_out` and the partner's share [−f_x, −f_y, −(m/ρ_i) q] to
/// `to_partner` (both the row's slices). Equations in [`crate::solver`]'s step 3.
///
/// `REFINED`: particles have their own masses and smoothing lengths (`table` is then the
/// unit kernel's, see [`variable_rows`]); the force on i is m_j (…)·∇W_ij and on j
/// −m_i (…)·∇W_ij, equal and opposite. Otherwise every particle has `k.mass` and `table`
/// is the model's kernel: the same operations on the same values as the refined form with
/// one mass, so a uniform model gives the same bits either way.
#[inline(always)]
pub(crate) fn force_row<const REFINED: bool>(
    i: usize,
    packed: &[Packed],
    partners: &[u32],
    table: &PairTable,
    k: &ForceConstants,
    wg_out: &mut [[f64; 2]],
    to_partner: &mut [[f64; 3]],
) -> ForceSums {
    let a = &packed[i];
    let m_a = if REFINED { a.m } else { k.mass };
    let mut sum_ax = [0.0; LANES];
    let mut sum_ay = [0.0; LANES];
    let mut sum_cond = [0.0; LANES];
    let mut sum_av = [0.0; LANES];
    for ((js, wg), to_j) in partners
        .chunks(LANES)
        .zip(wg_out.chunks_mut(LANES))
        .zip(to_partner.chunks_mut(LANES))
    {
        let n = js.len();
        // Padding lanes repeat particle i (zero distance); they are masked out below.
        let mut idx = [i; LANES];
        for (slot, &j) in idx.iter_mut().zip(js) {
            *slot = j as usize;
        }
        let (x_b, y_b) = (gather!(packed, idx, x), gather!(packed, idx, y));
        let (vx_b, vy_b) = (gather!(packed, idx, vx), gather!(packed, idx, vy));
        let (vol_b, inv_rho_b) = (gather!(packed, idx, vol), gather!(packed, idx, inv_rho));
        let (txx_b, txy_b, tyy_b) = (
            gather!(packed, idx, txx),
            gather!(packed, idx, txy),
            gather!(packed, idx, tyy),
        );
        let (rxx_b, rxy_b, ryy_b) = (
            gather!(packed, idx, rxx),
            gather!(packed, idx, rxy),
            gather!(packed, idx, ryy),
        );
        let (temp_b, k_b) = (gather!(packed, idx, temp), gather!(packed, idx, k));
        let dx: Lanes = std::array::from_fn(|l| a.x - x_b[l]);
        let dy: Lanes = std::array::from_fn(|l| a.y - y_b[l]);
        let r2: Lanes = std::array::from_fn(|l| dx[l] * dx[l] + dy[l] * dy[l]);
        // Branch-free: pairs in the skin (beyond 2h) get w = g = 0 and add nothing.
        let (rows, w_unit, m_b) = pair_rows::<REFINED>(table, k, a, packed, &idx, &r2);
        let mut fx = [0.0; LANES];
        let mut fy = [0.0; LANES];
        // The partner's acceleration (before its minus sign).
        let mut fx_b = [0.0; LANES];
        let mut fy_b = [0.0; LANES];
        let mut q = [0.0; LANES];
        let mut av = [0.0; LANES];
        for l in 0..LANES {
            let [_, g, g_cond, h_visc] = rows[l];
            let gx = g * dx[l];
            let gy = g * dy[l];
            let dvx = a.vx - vx_b[l];
            let dvy = a.vy - vy_b[l];
            // Monaghan viscosity for approaching pairs (μ = 0 otherwise).
            // 1/ρ̄ taken as the mean of 1/ρ (equal to 1/mean ρ to O((Δρ/ρ)²)).
            let closing = dvx * dx[l] + dvy * dy[l];
            let mu = h_visc * if closing < 0.0 { closing } else { 0.0 };
            let pi = (k.beta * mu - k.alpha * k.c_long) * mu * (a.inv_rho + inv_rho_b[l]);
            let f = w_unit[l] * k.inv_w_dx;
            let f2 = f * f;
            let f4 = k.artificial_stress_on * f2 * f2;
            let txx = a.txx + txx_b[l] - pi + f4 * (a.rxx + rxx_b[l]);
            let txy = a.txy + txy_b[l] + f4 * (a.rxy + rxy_b[l]);
            let tyy = a.tyy + tyy_b[l] - pi + f4 * (a.ryy + ryy_b[l]);
            let (sx, sy) = (txx * gx + txy * gy, txy * gx + tyy * gy);
            fx[l] = m_b[l] * sx;
            fy[l] = m_b[l] * sy;
            fx_b[l] = m_a * sx;
            fy_b[l] = m_a * sy;
            q[l] = (a.k + k_b[l]) * (a.temp - temp_b[l]) * g_cond;
            // The pair's whole dissipation (both partners) is booked on i.
            av[l] = m_a * m_b[l] * pi * (dvx * gx + dvy * gy);
        }
        for l in 0..LANES {
            sum_av[l] += masked(l, n, av[l]);
            sum_ax[l] += masked(l, n, fx[l]);
            sum_ay[l] += masked(l, n, fy[l]);
            sum_cond[l] += masked(l, n, vol_b[l] * q[l]);
        }
        for l in 0..n {
            wg[l] = [rows[l][0], rows[l][1]];
            to_j[l] = [-fx_b[l], -fy_b[l], -a.vol * q[l]];
        }
    }
    ForceSums {
        ax: sum_lanes(&sum_ax),
        ay: sum_lanes(&sum_ay),
        cond: sum_lanes(&sum_cond),
        av_power: sum_lanes(&sum_av),
    }
}

/// Kinematics sums of particle `i` with the new velocities: ρ̇, L_xx, L_xy, L_yx, L_yy and
/// the XSPH correction before ε (solver step 6), over its own row (`partners` with their
/// kernel values `own_wg`) and its incoming pairs (first partners `incoming_first`, kernel
/// values `pair_wg[incoming]`). This light pass stays one pair at a time, in row order:
/// gathering its six fields into lanes cost more than its ≈ 20 flops per pair saved
/// (measured: 2.1 s scalar against 3.2 s in lanes of eight over the same steps).
/// `REFINED`: each partner's own mass ([`Packed::m`]) instead of `m`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn kinematics_row<const REFINED: bool>(
    i: usize,
    packed: &[Packed],
    m: f64,
    partners: &[u32],
    own_wg: &[[f64; 2]],
    incoming: &[u32],
    incoming_first: &[u32],
    pair_wg: &[[f64; 2]],
) -> [f64; 7] {
    let a = &packed[i];
    let mut s = [0.0; 7];
    let mut add = |j: u32, [w, g]: [f64; 2]| {
        let b = &packed[j as usize];
        let m = if REFINED { b.m } else { m };
        let gx = g * (a.x - b.x);
        let gy = g * (a.y - b.y);
        let dvx = a.vx - b.vx;
        let dvy = a.vy - b.vy;
        s[0] += m * (dvx * gx + dvy * gy);
        s[1] -= b.vol * dvx * gx;
        s[2] -= b.vol * dvx * gy;
        s[3] -= b.vol * dvy * gx;
        s[4] -= b.vol * dvy * gy;
        let wv = 0.5 * m * (a.inv_rho + b.inv_rho) * w;
        s[5] -= wv * dvx;
        s[6] -= wv * dvy;
    };
    for (&j, &wg) in partners.iter().zip(own_wg) {
        add(j, wg);
    }
    for (&p, &f) in incoming.iter().zip(incoming_first) {
        add(f, pair_wg[p as usize]);
    }
    s
}

multiversion! {
    /// Force pass over the rows of particles `first..first + rates.len()`; `wg_out` and
    /// `force_out` are the per-pair outputs of those rows, starting at pair `pair0`;
    /// `refined`: per-particle masses and smoothing lengths (see [`force_row`]).
    pub(crate) fn force_rows(
        refined: bool,
        first: usize,
        rates: &mut [Rates],
        packed: &[Packed],
        nl: &NeighbourList,
        table: &PairTable,
        constants: &ForceConstants,
        wg_out: &mut [[f64; 2]],
        force_out: &mut [[f64; 3]],
        pair0: usize,
    ) {
        for (k, out) in rates.iter_mut().enumerate() {
            let i = first + k;
            let row = nl.pairs(i);
            let local = row.start - pair0..row.end - pair0;
            let (wg, force) = (&mut wg_out[local.clone()], &mut force_out[local]);
            let partners = nl.partners(i);
            let sums = if refined {
                force_row::<true>(i, packed, partners, table, constants, wg, force)
            } else {
                force_row::<false>(i, packed, partners, table, constants, wg, force)
            };
            out.ax = sums.ax;
            out.ay = sums.ay;
            out.dtemp = sums.cond;
            out.av_power = sums.av_power;
        }
    }
}

multiversion! {
    /// Kinematics pass over particles `first..first + rates.len()` (see [`kinematics_row`]).
    pub(crate) fn kinematics_rows(
        refined: bool,
        first: usize,
        rates: &mut [Rates],
        packed: &[Packed],
        nl: &NeighbourList,
        mass: f64,
        pair_wg: &[[f64; 2]],
    ) {
        for (k, out) in rates.iter_mut().enumerate() {
            let i = first + k;
            let (partners, own_wg) = (nl.partners(i), &pair_wg[nl.pairs(i)]);
            let (incoming, first_of) = (nl.incoming(i), nl.incoming_first(i));
            out.kin = if refined {
                kinematics_row::<true>(i, packed, mass, partners, own_wg, incoming, first_of, pair_wg)
            } else {
                kinematics_row::<false>(i, packed, mass, partners, own_wg, incoming, first_of, pair_wg)
            };
        }
    }
}
