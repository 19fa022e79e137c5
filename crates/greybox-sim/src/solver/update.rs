//! Step 7 of a step: drift, continuity, equation of state, Jaumann stress rate, radial
//! return, damage and heating, per chunk of particles in parallel, each particle by its own
//! step ([`Advance`]).

use super::{Advance, Derived, SimError, Solver};
use crate::particles::{mass_factor, spacing_factor};
use crate::plasticity;
use crate::rates::Rates;
use greybox_material::{JohnsonCookDamage, Thermal};
use rayon::prelude::*;

impl Solver {
    /// Step 7: drift, stress rate, plasticity, heating, checks — per chunk of particles in
    /// parallel ([`update_chunk`]), then the chunks' sums booked in chunk order; of the
    /// particles `advance` moves, each by its own step.
    pub(super) fn update(&mut self, advance: Advance<'_>) -> Result<(), SimError> {
        let d = self.derived;
        let (x0, y0, moved_lim2) = self.neighbours.reference();
        let inputs = UpdateInputs {
            dt: self.dt,
            advance,
            d,
            flow: self
                .material
                .plasticity
                .as_ref()
                .map(plasticity::YieldSurface::new),
            damage: self.material.damage.as_ref(),
            spacing: self.particles.spacing,
            th: &self.material.thermal,
            thermal: self.numerics.thermal,
            rate_scale: self.numerics.strain_rate_scale,
            f_mass: self.numerics.mass_scaling,
            vlim2: (self.numerics.max_speed_ratio * d.c_long).powi(2),
            m: self.particles.mass,
            eps_x: self.numerics.xsph,
            rates: &self.scratch.rates,
            x0,
            y0,
        };
        let p = &mut self.particles;
        const CH: usize = UPDATE_CHUNK;
        // (plastic work, max speed², first bad particle)
        (
            p.x.par_chunks_mut(CH),
            p.y.par_chunks_mut(CH),
            p.vx.par_chunks(CH),
            p.vy.par_chunks(CH),
            p.rho.par_chunks_mut(CH),
            p.p.par_chunks_mut(CH),
            p.sxx.par_chunks_mut(CH),
            p.sxy.par_chunks_mut(CH),
            p.syy.par_chunks_mut(CH),
            p.szz.par_chunks_mut(CH),
            p.eps_p.par_chunks_mut(CH),
            (
                p.temp.par_chunks_mut(CH),
                p.eps_rate.par_chunks_mut(CH),
                p.level.par_chunks(CH),
                p.damage.par_chunks_mut(CH),
            ),
        )
            .into_par_iter()
            .enumerate()
            .map(
                |(
                    c,
                    (x, y, vx, vy, rho, pr, sxx, sxy, syy, szz, eps, (temp, erate, level, damage)),
                )| {
                    let chunk = UpdateChunk {
                        x,
                        y,
                        vx,
                        vy,
                        rho,
                        pr,
                        sxx,
                        sxy,
                        syy,
                        szz,
                        eps,
                        temp,
                        erate,
                        level,
                        damage,
                    };
                    update_chunk(&inputs, c * CH, chunk)
                },
            )
            // Per-chunk sums in chunk order (an indexed collect), summed serially below:
            // the energy book is the same bytes on every run, whatever the thread schedule.
            .collect_into_vec(&mut self.scratch.chunk_sums);
        self.book_update(moved_lim2)
    }

    /// Step 7's sums: the plastic and viscous work booked, a rebuild noted when a particle
    /// moved too far, the first unstable particle reported.
    fn book_update(&mut self, moved_lim2: f64) -> Result<(), SimError> {
        let (mut plastic, mut viscous, mut bad) = (0.0, 0.0, usize::MAX);
        for &(wp, av, b, moved2) in &self.scratch.chunk_sums {
            plastic += wp;
            viscous += av;
            bad = bad.min(b);
            // NaN (an unstable particle) also forces a rebuild, never a missed pair.
            self.rebuild_due |= moved2 > moved_lim2 || moved2.is_nan();
        }
        self.energy.plastic_work += plastic;
        self.energy.viscous_work += self.dt * viscous;
        if bad != usize::MAX {
            return Err(self.instability(bad));
        }
        Ok(())
    }
}

/// Particles per parallel task of step 7.
const UPDATE_CHUNK: usize = 512;

/// What step 7 reads besides the particles: the step's constants, the rates of steps 3–6
/// and the positions the neighbour lists were built at.
struct UpdateInputs<'a> {
    /// Δt, s.
    dt: f64,
    /// Which particles move, by Δt or 2Δt.
    advance: Advance<'a>,
    d: Derived,
    flow: Option<plasticity::YieldSurface<'a>>,
    /// Ductile damage softening the flow stress; `None`: none.
    damage: Option<&'a JohnsonCookDamage>,
    /// Spacing of a level-0 particle, m (the length the damage's fracture energy is spread
    /// over).
    spacing: f64,
    th: &'a Thermal,
    /// Whether temperatures evolve (conduction and heating).
    thermal: bool,
    /// Factor on the strain rate seen by the flow stress (mass scaling's time scaling).
    rate_scale: f64,
    /// Mass scaling factor (the heat capacity uses the physical density ρ / f).
    f_mass: f64,
    /// Square of the largest allowed speed, m²/s².
    vlim2: f64,
    /// Mass (scaled) of a level-0 particle, kg/m.
    m: f64,
    /// XSPH factor ε.
    eps_x: f64,
    rates: &'a [Rates],
    x0: &'a [f64],
    y0: &'a [f64],
}

/// One chunk of the particle arrays in step 7, writable where the step writes.
struct UpdateChunk<'a> {
    x: &'a mut [f64],
    y: &'a mut [f64],
    vx: &'a [f64],
    vy: &'a [f64],
    rho: &'a mut [f64],
    pr: &'a mut [f64],
    sxx: &'a mut [f64],
    sxy: &'a mut [f64],
    syy: &'a mut [f64],
    szz: &'a mut [f64],
    eps: &'a mut [f64],
    temp: &'a mut [f64],
    erate: &'a mut [f64],
    level: &'a [u8],
    damage: &'a mut [f64],
}

/// Step 7 on one chunk whose first particle is `first`: (plastic work J/m, viscous power
/// W/m, first unstable particle or `usize::MAX`, largest squared displacement since the
/// neighbour build m²).
fn update_chunk(
    inp: &UpdateInputs<'_>,
    first: usize,
    mut ch: UpdateChunk<'_>,
) -> (f64, f64, usize, f64) {
    let mut wp = 0.0;
    let mut av = 0.0;
    let mut bad = usize::MAX;
    let mut moved2: f64 = 0.0;
    for k in 0..ch.x.len() {
        let i = first + k;
        let Some(dt) = inp.advance.step_of(i, inp.dt) else {
            continue;
        };
        let r = &inp.rates[i];
        av += r.av_power;
        moved2 = moved2.max(drift_and_stress_rate(inp, dt, r, i, k, &mut ch));
        if let Some(w) = plastic_and_heating(inp, dt, r, k, &mut ch) {
            wp += w;
        }
        if bad == usize::MAX && unstable(inp, k, &ch) {
            bad = i;
        }
    }
    (wp, av, bad, moved2)
}

/// Drift with the XSPH velocity, continuity, equation of state and the Jaumann stress rate of
/// particle `i` (`k` in the chunk) over its step `dt`; returns its squared displacement since
/// the neighbour build, m².
fn drift_and_stress_rate(
    inp: &UpdateInputs<'_>,
    dt: f64,
    r: &Rates,
    i: usize,
    k: usize,
    ch: &mut UpdateChunk<'_>,
) -> f64 {
    let (d, eps_x) = (inp.d, inp.eps_x);
    let [drho, lxx, lxy, lyx, lyy, xsx, xsy] = r.kin;
    let (nvx, nvy) = (ch.vx[k], ch.vy[k]);
    ch.x[k] += dt * (nvx + eps_x * xsx);
    ch.y[k] += dt * (nvy + eps_x * xsy);
    let moved2 = (ch.x[k] - inp.x0[i]).powi(2) + (ch.y[k] - inp.y0[i]).powi(2);
    ch.rho[k] += dt * drho;
    ch.pr[k] = d.c0_sq * (ch.rho[k] - d.rho0);
    if let Some(damage) = inp.damage {
        ch.pr[k] *= damage.mean_stress_share(ch.damage[k], ch.pr[k] < 0.0);
    }
    let [nxx, nxy, nyy, dzz] = jaumann_update(
        [ch.sxx[k], ch.sxy[k], ch.syy[k]],
        lxx,
        lxy,
        lyx,
        lyy,
        d.shear,
        dt,
    );
    ch.sxx[k] = nxx;
    ch.sxy[k] = nxy;
    ch.syy[k] = nyy;
    ch.szz[k] += dzz;
    moved2
}

/// Conduction heating, the radial return and its plastic heating of particle `k` of the
/// chunk over its step `dt`; returns its plastic work (m/ρ) σ_y Δε_p, J/m, when it yielded.
fn plastic_and_heating(
    inp: &UpdateInputs<'_>,
    dt: f64,
    r: &Rates,
    k: usize,
    ch: &mut UpdateChunk<'_>,
) -> Option<f64> {
    let mut t_new = ch.temp[k];
    if inp.thermal {
        t_new += dt * r.dtemp;
    }
    let previous_increment = ch.erate[k] * dt;
    ch.erate[k] = 0.0;
    let mut work = None;
    if let Some(flow) = inp.flow {
        let mut s = [ch.sxx[k], ch.sxy[k], ch.syy[k], ch.szz[k]];
        let strength = inp.damage.map_or(1.0, |m| m.strength(ch.damage[k]));
        let state = plasticity::State {
            eps_p: ch.eps[k],
            temperature_k: ch.temp[k],
            dt,
            rate_scale: inp.rate_scale,
            guess: previous_increment,
            strength,
        };
        if let Some(ret) = plasticity::radial_return(&flow, inp.d.shear, &mut s, state) {
            if let Some(damage) = inp.damage {
                advance_damage(inp, dt, damage, &ret, strength, k, ch);
            }
            ch.sxx[k] = s[0];
            ch.sxy[k] = s[1];
            ch.syy[k] = s[2];
            ch.szz[k] = s[3];
            ch.eps[k] += ret.d_eps;
            ch.erate[k] = ret.d_eps / dt;
            // Plastic work per volume σ_y Δε_p; volume m/ρ.
            let wv = ret.flow_stress * ret.d_eps;
            work = Some(wv * (inp.m * mass_factor(ch.level[k])) / ch.rho[k]);
            if inp.thermal {
                let c = inp.th.specific_heat.eval(ch.temp[k]);
                t_new += inp.th.taylor_quinney * wv / (ch.rho[k] / inp.f_mass * c);
            }
        }
    }
    ch.temp[k] = t_new;
    work
}

/// The damage of particle `k` after its plastic increment `ret` (before the chunk's state
/// takes the increment): the triaxiality −p/σ_vm with σ_vm the flow stress the return landed
/// on, the rate as the flow stress sees it, the undamaged flow stress σ_y = σ/(1 − d).
fn advance_damage(
    inp: &UpdateInputs<'_>,
    dt: f64,
    damage: &JohnsonCookDamage,
    ret: &plasticity::Return,
    strength: f64,
    k: usize,
    ch: &mut UpdateChunk<'_>,
) {
    let triaxiality = if ret.flow_stress > 0.0 {
        -ch.pr[k] / ret.flow_stress
    } else {
        0.0
    };
    ch.damage[k] = damage.advance(
        ch.damage[k],
        ret.d_eps,
        triaxiality,
        inp.rate_scale * ret.d_eps / dt,
        ch.temp[k],
        ret.flow_stress / strength,
        inp.spacing * spacing_factor(ch.level[k]),
    );
}

/// Whether particle `k` of the chunk is unstable after step 7: a non-finite state, a speed
/// above the limit or a non-positive density.
fn unstable(inp: &UpdateInputs<'_>, k: usize, ch: &UpdateChunk<'_>) -> bool {
    let (nvx, nvy) = (ch.vx[k], ch.vy[k]);
    let v2 = nvx * nvx + nvy * nvy;
    let finite = ch.x[k].is_finite()
        && ch.y[k].is_finite()
        && ch.rho[k].is_finite()
        && ch.sxx[k].is_finite()
        && ch.sxy[k].is_finite()
        && ch.syy[k].is_finite()
        && ch.temp[k].is_finite();
    !finite || v2 > inp.vlim2 || ch.rho[k] <= 0.0
}

/// The deviatoric stress (s_xx, s_xy, s_yy) advanced by `dt` with its Jaumann rate under the
/// velocity gradient L (plane strain, shear modulus G): ṡ = 2G (D − tr D/3 I) + W s − s W.
/// Returns the new (s_xx, s_xy, s_yy) and the increment of s_zz.
#[inline(always)]
fn jaumann_update(
    [oxx, oxy, oyy]: [f64; 3],
    lxx: f64,
    lxy: f64,
    lyx: f64,
    lyy: f64,
    shear: f64,
    dt: f64,
) -> [f64; 4] {
    let dxx = lxx;
    let dyy = lyy;
    let dxy = 0.5 * (lxy + lyx);
    let w = 0.5 * (lxy - lyx);
    let tr3 = (dxx + dyy) / 3.0;
    let g2 = 2.0 * shear;
    [
        oxx + dt * (g2 * (dxx - tr3) + 2.0 * w * oxy),
        oxy + dt * (g2 * dxy + w * (oyy - oxx)),
        oyy + dt * (g2 * (dyy - tr3) - 2.0 * w * oxy),
        dt * (-g2 * tr3),
    ]
}
