//! The per-time-step content of a recording (`time` timeline, seconds; m = 0..=N of METHOD §2):
//! deformed surfaces coloured by nodal von Mises stress (viridis, one range over the whole run,
//! recorded), subsampled nodal velocity arrows, and on contact interfaces the pressure p = −F̂₁·n
//! at each node, the step-averaged normal force and the largest slip (METHOD §5, post).

use super::surface::Surface;
use super::{entity_name, StepsSummary, MAX_ARROWS};
use anyhow::Context;
use lopin_core::post;
use lopin_core::{Solution, Solver};
use lopin_explorer::colormap::{self, Range};
use lopin_explorer::fields::element_to_nodes;

fn rgb(c: [f32; 3]) -> rerun::Color {
    let q = |x: f32| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
    rerun::Color::from_rgb(q(c[0]), q(c[1]), q(c[2]))
}

fn set_context(rec: &rerun::RecordingStream, context: &[(&'static str, i64)]) {
    for (timeline, value) in context {
        rec.set_time_sequence(*timeline, *value);
    }
}

/// Logs every step of `sol` (`history`: [`post::history`] of it); the surfaces' triangles are logged (static) when `topology`.
pub fn log(
    rec: &rerun::RecordingStream,
    solver: &Solver,
    sol: &Solution,
    history: &[Vec<post::SubFields>],
    context: &[(&'static str, i64)],
    deform: Option<f64>,
    topology: bool,
) -> anyhow::Result<StepsSummary> {
    let p = solver.problem();
    let surfaces: Vec<Surface> = p.subs.iter().map(|s| Surface::of(&s.mesh)).collect();
    let von_mises: Vec<Vec<Vec<f64>>> = history
        .iter()
        .enumerate()
        .map(|(i, steps)| {
            steps
                .iter()
                .map(|f| element_to_nodes(&p.subs[i].mesh, &post::von_mises(solver, i, &f.u)))
                .collect()
        })
        .collect();
    let vm_range = colormap::resolve(
        Range::Auto,
        von_mises
            .iter()
            .zip(&surfaces)
            .flat_map(|(steps, s)| steps.iter().flat_map(|vm| s.pick(vm))),
    );
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for s in &p.subs {
        let (a, b) = s.mesh.bounding_box();
        for c in 0..3 {
            lo[c] = lo[c].min(a[c]);
            hi[c] = hi[c].max(b[c]);
        }
    }
    let diag = (0..3).map(|c| (hi[c] - lo[c]).powi(2)).sum::<f64>().sqrt();
    let max_norm = |pick: fn(&post::SubFields) -> &Vec<f64>| {
        history
            .iter()
            .flatten()
            .flat_map(|f| {
                pick(f)
                    .chunks_exact(3)
                    .map(|x| x.iter().map(|a| a * a).sum::<f64>())
            })
            .fold(0.0_f64, f64::max)
            .sqrt()
    };
    let (umax, vmax) = (max_norm(|f| &f.u), max_norm(|f| &f.v));
    let scale = deform.unwrap_or(if umax > 0.0 { 0.05 * diag / umax } else { 1.0 });
    let arrow_scale = if vmax > 0.0 { 0.1 * diag / vmax } else { 1.0 };
    let total_nodes: usize = p.subs.iter().map(|s| s.mesh.nodes.len()).sum();
    let stride = total_nodes.div_ceil(MAX_ARROWS).max(1);
    let contacts = post::contact(solver, sol);
    let pressure_max = contacts
        .iter()
        .flat_map(|c| c.pressure.iter().flatten())
        .copied()
        .fold(0.0_f64, f64::max);
    let radius = (0.004 * diag) as f32;

    if topology {
        for (s, surf) in p.subs.iter().zip(&surfaces) {
            rec.log_static(
                format!("bodies/{}/surface", entity_name(&s.name)),
                &rerun::Mesh3D::update_fields().with_triangle_indices(surf.triangles.clone()),
            )
            .context("rerun: logging a surface")?;
        }
    }
    set_context(rec, context);
    rec.set_duration_secs("time", 0.0);
    rec.log(
        "colormap",
        &rerun::TextDocument::from_markdown(format!(
            "Surfaces: von Mises stress, viridis, {:.4} MPa (dark) to {:.4} MPa (bright), one range over the run. \
             Displacements drawn ×{scale:.4e}. Velocity arrows: 1 m/s drawn {arrow_scale:.4e} m long, {every}. \
             Contact points: pressure, 0 (dark) to {:.4} MPa (bright).",
            vm_range.0 * 1e-6,
            vm_range.1 * 1e-6,
            pressure_max * 1e-6,
            every = if stride == 1 {
                "at every node".to_string()
            } else {
                format!("at one node in {stride}")
            }
        )),
    )?;
    for m in 0..=p.time.steps {
        set_context(rec, context);
        rec.set_duration_secs("time", p.time.time(m));
        let mut counter = 0usize;
        for (i, s) in p.subs.iter().enumerate() {
            let f = &history[i][m];
            let name = entity_name(&s.name);
            let colors: Vec<rerun::Color> = surfaces[i]
                .pick(&von_mises[i][m])
                .iter()
                .map(|&v| rgb(colormap::color(v, vm_range.0, vm_range.1)))
                .collect();
            rec.log(
                format!("bodies/{name}/surface"),
                &rerun::Mesh3D::update_fields()
                    .with_vertex_positions(surfaces[i].positions(&s.mesh, &f.u, scale))
                    .with_vertex_colors(colors),
            )?;
            let (mut origins, mut vectors) = (Vec::new(), Vec::new());
            for n in 0..s.mesh.nodes.len() {
                counter += 1;
                if !counter.is_multiple_of(stride) {
                    continue;
                }
                let x = s.mesh.nodes[n];
                origins.push(std::array::from_fn::<f32, 3, _>(|c| {
                    (x[c] + scale * f.u[3 * n + c]) as f32
                }));
                vectors.push(std::array::from_fn::<f32, 3, _>(|c| {
                    (arrow_scale * f.v[3 * n + c]) as f32
                }));
            }
            rec.log(
                format!("bodies/{name}/velocity"),
                &rerun::Arrows3D::from_vectors(vectors).with_origins(origins),
            )?;
        }
        for c in &contacts {
            let iface = &p.interfaces[c.interface];
            let name = format!("contact/{}", entity_name(&iface.name));
            let side = &iface.sides[0];
            let (mesh, u) = (&p.subs[side.sub].mesh, &history[side.sub][m].u);
            let positions: Vec<[f32; 3]> = side
                .nodes
                .iter()
                .map(|&n| std::array::from_fn(|q| (mesh.nodes[n][q] + scale * u[3 * n + q]) as f32))
                .collect();
            let colors: Vec<rerun::Color> = c.pressure[m]
                .iter()
                .map(|&pr| rgb(colormap::color(pr, 0.0, pressure_max.max(1e-300))))
                .collect();
            rec.log(
                format!("{name}/pressure"),
                &rerun::Points3D::new(positions)
                    .with_colors(colors)
                    .with_radii([radius]),
            )?;
            rec.log(
                format!("{name}/normal_force"),
                &rerun::Scalars::single(c.normal_force[m]),
            )?;
            let slip = c.slip[m].iter().copied().fold(0.0_f64, f64::max);
            rec.log(format!("{name}/max_slip"), &rerun::Scalars::single(slip))?;
        }
    }
    rec.disable_timeline("time");
    for (timeline, _) in context {
        rec.disable_timeline(*timeline);
    }
    Ok(StepsSummary {
        steps: p.time.steps + 1,
        von_mises: vm_range,
        deform: scale,
        arrow_scale,
        pressure_max,
    })
}
