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
    /// Contact length per particle (the particle spacing), m.
    pub spacing: f64,
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
    let lx = p.x[i] - tool.position[0];
    let ly = p.y[i] - tool.position[1];
    if lx < lo[0] - reach || lx > hi[0] + reach || ly < lo[1] - reach || ly > hi[1] + reach {
        return None;
    }
    let sp = tool.shape.closest([lx, ly]);
    (sp.distance < 0.0 && p.group[i] == FREE).then_some(sp)
}

/// Whether any particle touches any tool: whether [`apply`] would make a contact force.
pub(crate) fn any(tools: &[Tool], p: &Particles, reach: f64) -> bool {
    tools.iter().any(|tool| {
        let tool_box = tool.shape.bounding_box();
        (0..p.len()).any(|i| contact_point(tool, tool_box, reach, p, i).is_some())
    })
}

#[allow(clippy::needless_range_loop)] // several arrays are indexed by i
pub(crate) fn apply(
    c: &ContactParams,
    p: &mut Particles,
    rates: &mut [Rates],
    tools: &mut [Tool],
) -> ContactWork {
    let (dt, t, alpha, reach, heat, f_mass, th) = (
        c.dt,
        c.time,
        c.penalty,
        c.reach,
        c.heat_share,
        c.mass_scaling,
        c.thermal,
    );
    let m = p.mass;
    let mut friction_work = 0.0;
    let mut penalty_work = 0.0;
    let mut external_work = 0.0;
    let mut tool_heat = 0.0;
    let dx_p = c.spacing;
    for tool in tools.iter_mut() {
        let vt = tool.motion.velocity(t);
        let (lo, hi) = tool.shape.bounding_box();
        let (x0, y0) = (tool.position[0], tool.position[1]);
        let mut force = [0.0f64; 2];
        let mut contacts = 0usize;
        for w in tool.windows.iter_mut() {
            w.acc.steps += 1;
        }
        for i in 0..p.len() {
            let Some(sp) = contact_point(tool, (lo, hi), reach, p, i) else {
                continue;
            };
            let (lx, ly) = (p.x[i] - x0, p.y[i] - y0);
            let n = sp.normal;
            let fn_ = -alpha * m * sp.distance / (dt * dt);
            let rvx = p.vx[i] - vt[0];
            let rvy = p.vy[i] - vt[1];
            let rvn = rvx * n[0] + rvy * n[1];
            let (tvx, tvy) = (rvx - rvn * n[0], rvy - rvn * n[1]);
            // Stick predictor: relative tangential velocity after the step without friction.
            let (ax, ay) = (rates[i].ax, rates[i].ay);
            let an = ax * n[0] + ay * n[1];
            let ux = tvx + dt * (ax - an * n[0]);
            let uy = tvy + dt * (ay - an * n[1]);
            let mut ftx = -m * ux / dt;
            let mut fty = -m * uy / dt;
            let win = tool.window_at(sp.s);
            let mu = win.map_or(0.0, |k| tool.windows[k].mu);
            let ft = ftx.hypot(fty);
            let cap = mu * fn_;
            let slipping = ft > cap;

            if slipping {
                let s = cap / ft;
                ftx *= s;
                fty *= s;
            }
            let fx = fn_ * n[0] + ftx;
            let fy = fn_ * n[1] + fty;
            rates[i].ax += fx / m;
            rates[i].ay += fy / m;
            force[0] -= fx;
            force[1] -= fy;
            contacts += 1;
            // Work of the contact force on the mid-step relative velocity, split normal /
            // tangential (consistent with the kinetic-energy change of the kick).
            let mvx = rvx + 0.5 * dt * rates[i].ax;
            let mvy = rvy + 0.5 * dt * rates[i].ay;
            let mvn = mvx * n[0] + mvy * n[1];
            let slip_power = -(ftx * (mvx - mvn * n[0]) + fty * (mvy - mvn * n[1]));
            friction_work += slip_power * dt;
            penalty_work -= fn_ * mvn * dt;
            external_work += (fx * vt[0] + fy * vt[1]) * dt;
            let cp = th.specific_heat.eval(p.temp[i]);
            if heat > 0.0 && slip_power > 0.0 {
                rates[i].dtemp += heat * slip_power / (m / f_mass * cp);
            }
            let mut t_tool = 0.0;
            if let (Some(tt), true) = (tool.thermal.as_mut(), c.thermal_on) {
                // The contact point on the surface, half a tool cell inside.
                let d = sp.distance + 0.5 * tt.dx;
                let cell = tt.cell_at([lx - n[0] * d, ly - n[1] * d]);
                t_tool = tt.temp[cell];
                // Conduction across coating and interface, W/m, and the tool's share of the
                // friction heat.
                let q = tt.conductance(t_tool) * (p.temp[i] - t_tool) * dx_p;
                rates[i].dtemp -= q / (m / f_mass * cp);
                let into_tool = (q + (1.0 - heat) * slip_power.max(0.0)) * dt;
                tt.heat_in[cell] += into_tool;
                tool_heat += into_tool;
            }
            let vslip = tvx.hypot(tvy) * c.velocity_scale;
            if let Some(k) = win {
                let a = &mut tool.windows[k].acc;
                a.contacts += 1.0;
                a.normal += fn_;
                a.tangential += ftx.hypot(fty);
                a.normal_x_slip += fn_ * vslip;
                a.normal_x_temp += fn_ * p.temp[i];
                a.normal_x_tool_temp += fn_ * t_tool;
                if slipping {
                    a.slipping += 1.0;
                }
            }
        }
        tool.force = force;
        tool.contacts = contacts;
        if let (Some(tt), true) = (tool.thermal.as_mut(), c.thermal_on) {
            tt.after_step(dt);
        }
    }
    ContactWork {
        friction: friction_work,
        penalty: penalty_work,
        external: external_work,
        tool_heat,
    }
}
