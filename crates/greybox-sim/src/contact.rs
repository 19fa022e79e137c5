//! Rigid-tool contact: penalty normal force and Coulomb friction with a stick predictor and
//! slip return (the kinematic predictor of explicit FE contact, e.g. Abaqus/Explicit; the ETH
//! IWF SPH codes use the penalty-spring variant of the same idea).
//!
//! For a particle at signed distance g < 0 from the tool surface (outward normal n):
//! * normal force f_N = −α m g / Δt² along n (α = `contact_penalty`);
//! * stick predictor: the tangential force that makes the particle's tangential velocity equal
//!   the tool's after this step, f* = −m (v_t + Δt a_t) / Δt, with v_t the relative tangential
//!   velocity and a_t the tangential part of the internal (SPH) acceleration;
//! * slip return: if |f*| > μ f_N then f_t = μ f_N f*/|f*| (sliding), else f_t = f*
//!   (sticking); μ is that of the friction window containing the contact point.
//!
//! Unlike a tangential penalty spring this predictor has no memory and does not chatter
//! between stick and slip, so a sliding contact carries exactly μ f_N.
//!
//! The window accumulates f_N, |f_t|, f_N·|v_t| and f_N·T for its time averages; the friction
//! work (f_t on the mid-step relative velocity) heats the particle (share
//! `friction_heat_share`); a thermal tool takes the rest of it, and exchanges heat with
//! the particle through the interface conductance (see [`crate::tool_thermal`]).

use crate::particles::{Particles, FREE};
use crate::rates::Rates;
use crate::tool::Tool;
use greybox_material::Thermal;

/// What contact needs of the solver besides the particles, their rates and the tools.
pub(crate) struct ContactParams<'a> {
    /// Time step and time, s.
    pub dt: f64,
    pub time: f64,
    /// Penalty factor α (`contact_penalty`).
    pub penalty: f64,
    /// Reach around a tool's bounding box (the smoothing length), m.
    pub reach: f64,
    /// Share of the friction work that heats the particle (0 when not thermal).
    pub heat_share: f64,
    /// Mass scaling factor (heat capacity per volume stays physical).
    pub mass_scaling: f64,
    /// Heat conduction on (a thermal tool exchanges heat only then).
    pub thermal_on: bool,
    /// Physical over simulated speed (`strain_rate_scale`): windows record physical sliding
    /// velocities in time-scaled runs.
    pub velocity_scale: f64,
    pub thermal: &'a Thermal,
}

/// Work of the contact forces in one step, J/m.
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct ContactWork {
    pub friction: f64,
    pub penalty: f64,
    pub external: f64,
    /// Heat into thermal tools (conduction across the interface and their share of the
    /// friction heat), J/m.
    pub tool_heat: f64,
}

/// Particle `i`'s closest point on `tool` when the particle is free and inside the tool
/// (signed distance < 0), the one case that makes a contact force; `tool_box` is the
/// shape's bounding box, widened by `reach` as a first, cheap test.
#[inline]
fn contact_point(
    tool: &Tool,
    (lo, hi): ([f64; 2], [f64; 2]),
    reach: f64,
    p: &Particles,
    i: usize,
) -> Option<crate::geometry::SurfacePoint> {
    let local = in_box(tool, (lo, hi), reach, p, i)?;
    if tool.shape.surely_clear(local, 0.0) {
        return None;
    }
    let sp = tool.shape.closest(local);
    (sp.distance < 0.0 && p.group[i] == FREE).then_some(sp)
}

/// Particle `i`'s position in `tool`'s frame when it lies within `reach` of the tool's
/// bounding box `(lo, hi)` (a cheap first test).
#[inline]
fn in_box(
    tool: &Tool,
    (lo, hi): ([f64; 2], [f64; 2]),
    reach: f64,
    p: &Particles,
    i: usize,
) -> Option<[f64; 2]> {
    let lx = p.x[i] - tool.position[0];
    let ly = p.y[i] - tool.position[1];
    let outside =
        lx < lo[0] - reach || lx > hi[0] + reach || ly < lo[1] - reach || ly > hi[1] + reach;
    (!outside).then_some([lx, ly])
}

/// Sets `near[i]` for every particle closer than `distance` to a tool's surface (or inside
/// a tool), leaving the others as they are.
pub(crate) fn mark_near(tools: &[Tool], p: &Particles, distance: f64, near: &mut [bool]) {
    use rayon::prelude::*;
    for tool in tools {
        let tool_box = tool.shape.bounding_box();
        near.par_iter_mut().enumerate().for_each(|(i, near)| {
            if !*near {
                *near = in_box(tool, tool_box, distance, p, i).is_some_and(|local| {
                    !tool.shape.surely_clear(local, distance)
                        && tool.shape.closest(local).distance < distance
                });
            }
        });
    }
}

/// Whether any particle touches any tool: whether [`apply`] would make a contact force.
pub(crate) fn any(tools: &[Tool], p: &Particles, reach: f64) -> bool {
    tools.iter().any(|tool| {
        let tool_box = tool.shape.bounding_box();
        (0..p.len()).any(|i| contact_point(tool, tool_box, reach, p, i).is_some())
    })
}

/// Step 4 for every tool: the contact force of every particle inside it added to the
/// particle's acceleration, the tool's reaction force and contact count, the friction
/// windows' sums, friction heating and a thermal tool's exchange; returns the step's work.
pub(crate) fn apply(
    c: &ContactParams,
    p: &mut Particles,
    rates: &mut [Rates],
    tools: &mut [Tool],
) -> ContactWork {
    let mut work = ContactWork::default();
    for tool in tools.iter_mut() {
        apply_tool(c, p, rates, tool, &mut work);
        if let (Some(tt), true) = (tool.thermal.as_mut(), c.thermal_on) {
            tt.after_step(c.dt);
        }
    }
    work
}

/// The contact of every particle with one tool (see [`apply`]), its work added to `work`.
#[allow(clippy::needless_range_loop)] // the particles' arrays and the rates are indexed by i
fn apply_tool(
    c: &ContactParams,
    p: &mut Particles,
    rates: &mut [Rates],
    tool: &mut Tool,
    work: &mut ContactWork,
) {
    let (dt, heat, f_mass, th) = (c.dt, c.heat_share, c.mass_scaling, c.thermal);
    let vt = tool.motion.velocity(c.time);
    let tool_box = tool.shape.bounding_box();
    let mut force = [0.0f64; 2];
    let mut contacts = 0usize;
    for w in tool.windows.iter_mut() {
        w.acc.steps += 1;
    }
    for i in 0..p.len() {
        let Some(sp) = contact_point(tool, tool_box, c.reach, p, i) else {
            continue;
        };
        let m = p.mass_of(i);
        let pc = stick_slip(c, m, tool, vt, &sp, p, &rates[i], i);
        let n = sp.normal;
        let fx = pc.fn_ * n[0] + pc.ftx;
        let fy = pc.fn_ * n[1] + pc.fty;
        let r = &mut rates[i];
        r.ax += fx / m;
        r.ay += fy / m;
        force[0] -= fx;
        force[1] -= fy;
        contacts += 1;
        let slip_power = book_work(&pc, n, [fx, fy], vt, dt, r, work);
        let cp = th.specific_heat.eval(p.temp[i]);
        if heat > 0.0 && slip_power > 0.0 {
            r.dtemp += heat * slip_power / (m / f_mass * cp);
        }
        let t_tool = exchange_heat(c, m, cp, slip_power, tool, &sp, p, i, r, work);
        let vslip = pc.tv[0].hypot(pc.tv[1]) * c.velocity_scale;
        // The particle's share of the contact length, in level-0 spacings.
        let share = p.spacing_of(i) / p.spacing;
        record_in_window(tool, &pc, share, vslip, p.temp[i], t_tool);
    }
    tool.force = force;
    tool.contacts = contacts;
}

/// One particle's contact force on a tool, before it is applied.
struct ParticleContact {
    /// Normal penalty force f_N = −α m g / Δt², N/m.
    fn_: f64,
    /// Tangential (friction) force after the slip return, N/m.
    ftx: f64,
    fty: f64,
    /// Whether the stick force exceeded μ f_N (the particle slides).
    slipping: bool,
    /// Velocity relative to the tool, m/s.
    rv: [f64; 2],
    /// Its tangential part, m/s.
    tv: [f64; 2],
    /// The friction window of the contact point.
    win: Option<usize>,
}

/// The penalty normal force and the stick predictor with its slip return (module doc) of
/// particle `i` at the surface point `sp` of a tool moving at `vt`.
#[allow(clippy::too_many_arguments)]
fn stick_slip(
    c: &ContactParams,
    m: f64,
    tool: &Tool,
    vt: [f64; 2],
    sp: &crate::geometry::SurfacePoint,
    p: &Particles,
    rate: &Rates,
    i: usize,
) -> ParticleContact {
    let dt = c.dt;
    let n = sp.normal;
    let fn_ = -c.penalty * m * sp.distance / (dt * dt);
    let rvx = p.vx[i] - vt[0];
    let rvy = p.vy[i] - vt[1];
    let rvn = rvx * n[0] + rvy * n[1];
    let (tvx, tvy) = (rvx - rvn * n[0], rvy - rvn * n[1]);
    // Stick predictor: relative tangential velocity after the step without friction.
    let (ax, ay) = (rate.ax, rate.ay);
    let an = ax * n[0] + ay * n[1];
    let ux = tvx + dt * (ax - an * n[0]);
    let uy = tvy + dt * (ay - an * n[1]);
    let mut ftx = -m * ux / dt;
    let mut fty = -m * uy / dt;
    let win = tool.window_at(sp.s);
    let mu = win.map_or(0.0, |k| tool.windows[k].mu);
    let ft = ftx.hypot(fty);
    // Coulomb's μ f_N, and at most the limiting shear stress over the particle's share of
    // the surface (its spacing; forces per unit depth).
    let coulomb = mu * fn_;
    let cap = tool
        .shear_limit_pa
        .map_or(coulomb, |tau| coulomb.min(tau * p.spacing_of(i)));
    let slipping = ft > cap;
    if slipping {
        let s = cap / ft;
        ftx *= s;
        fty *= s;
    }
    ParticleContact {
        fn_,
        ftx,
        fty,
        slipping,
        rv: [rvx, rvy],
        tv: [tvx, tvy],
        win,
    }
}

/// Work of the contact force `f` on the mid-step relative velocity, split normal /
/// tangential (consistent with the kinetic-energy change of the kick), added to `work`;
/// returns the slip power −f_t·v_t, W/m.
fn book_work(
    pc: &ParticleContact,
    n: [f64; 2],
    f: [f64; 2],
    vt: [f64; 2],
    dt: f64,
    rate: &Rates,
    work: &mut ContactWork,
) -> f64 {
    let mvx = pc.rv[0] + 0.5 * dt * rate.ax;
    let mvy = pc.rv[1] + 0.5 * dt * rate.ay;
    let mvn = mvx * n[0] + mvy * n[1];
    let slip_power = -(pc.ftx * (mvx - mvn * n[0]) + pc.fty * (mvy - mvn * n[1]));
    work.friction += slip_power * dt;
    work.penalty -= pc.fn_ * mvn * dt;
    work.external += (f[0] * vt[0] + f[1] * vt[1]) * dt;
    slip_power
}

/// A thermal tool's exchange with particle `i` (heat capacity `cp`, J/(kg·K)): conduction
/// across coating and interface and the tool's share of the friction heat; returns the
/// tool's temperature at the contact point, K (0 for an adiabatic tool).
#[allow(clippy::too_many_arguments)]
fn exchange_heat(
    c: &ContactParams,
    m: f64,
    cp: f64,
    slip_power: f64,
    tool: &mut Tool,
    sp: &crate::geometry::SurfacePoint,
    p: &Particles,
    i: usize,
    rate: &mut Rates,
    work: &mut ContactWork,
) -> f64 {
    let (Some(tt), true) = (tool.thermal.as_mut(), c.thermal_on) else {
        return 0.0;
    };
    let (lx, ly) = (p.x[i] - tool.position[0], p.y[i] - tool.position[1]);
    let n = sp.normal;
    // The contact point on the surface, half a tool cell inside.
    let d = sp.distance + 0.5 * tt.dx;
    let cell = tt.cell_at([lx - n[0] * d, ly - n[1] * d]);
    let t_tool = tt.temp[cell];
    // Conduction across coating and interface, W/m, and the tool's share of the friction
    // heat.
    let q = tt.conductance(t_tool) * (p.temp[i] - t_tool) * p.spacing_of(i);
    rate.dtemp -= q / (m / c.mass_scaling * cp);
    let into_tool = (q + (1.0 - c.heat_share) * slip_power.max(0.0)) * c.dt;
    tt.heat_in[cell] += into_tool;
    work.tool_heat += into_tool;
    t_tool
}

/// Adds one particle's contact to its window's sums (`share` the contact length it stands
/// for in level-0 spacings, 1 on an unrefined model; `vslip` physical sliding speed, m/s;
/// `temp_k` the particle's and `tool_temp_k` the tool's temperature, K).
fn record_in_window(
    tool: &mut Tool,
    pc: &ParticleContact,
    share: f64,
    vslip: f64,
    temp_k: f64,
    tool_temp_k: f64,
) {
    let Some(k) = pc.win else {
        return;
    };
    let a = &mut tool.windows[k].acc;
    a.contacts += share;
    a.normal += pc.fn_;
    a.tangential += pc.ftx.hypot(pc.fty);
    a.normal_x_slip += pc.fn_ * vslip;
    a.normal_x_temp += pc.fn_ * temp_k;
    a.normal_x_tool_temp += pc.fn_ * tool_temp_k;
    if pc.slipping {
        a.slipping += share;
    }
}
