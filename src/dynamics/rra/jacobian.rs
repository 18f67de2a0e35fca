//! The Gauss–Newton normal equations of residual reduction ([`super::problem`]): per counted
//! frame, the residual `r = [n; h f]` and how each parameter changes it — the trunk offset and
//! the pelvis rotation by finite differences of the needed wrench (from the root-relative terms,
//! [`super::relative`], or else RNEA), the pelvis offset in closed form, the mass scale by
//! linearity — frames in parallel, summed in frame order.

use super::Ground;
use super::problem::{Evaluated, Layout, NT, Problem, with_mass_scale};
use super::relative::{Composite, RootRelative};
use super::root::{BodyRotation, RootRotation, rotate_root};
use crate::dynamics::grf::{GroundReactions, about, root_wrench};
use crate::dynamics::residual::{centre_of_mass, with_trunk_offset};
use crate::dynamics::{
    Workspace, forward_kinematics, forward_kinematics_through, last_root_level_body, rnea,
};
use crate::model::Model;
use crate::spatial::ForceVec;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

/// A residual this small is met, as a share of the body's weight `M g` (force) and of `M g h`
/// (moment about the pelvis, `h` the mean COM height): the feet give the wrench there. Relative,
/// so that the reduction of a body whose every mass is scaled alike takes the same steps and
/// ends at the same adjustments (a knee study across body weights compares like with like).
const MET: f64 = 1e-6;
/// The step of the trunk offset's finite differences (m); the needed wrench is linear in the
/// first moments `mᵢ cᵢ`, nearly so in `cᵢ` (the parallel-axis term is second order).
const TRUNK_STEP: f64 = 0.005;
/// The step of the rotation's finite differences (rad, rad/s, rad/s²): the needed wrench is
/// linear in the angular acceleration, smooth in the angle and rate.
const ROTATION_STEP: f64 = 1e-6;

/// What one frame's residual does with a change of the needed wrench (about the pelvis):
/// passed whole in flight and against measured forces; with estimated forces in stance, the
/// moment where a clamp holds, less the moment of the force change at the feet's centre of
/// pressure `cop`, and the force where one holds.
struct Pass {
    whole: bool,
    moment_clamped: bool,
    force_clamped: bool,
    lever: Vector3<f64>,
    height: f64,
}

impl Pass {
    fn new(
        g: &GroundReactions,
        k: usize,
        pelvis: &Vector3<f64>,
        height: f64,
        measured: bool,
        weight: f64,
    ) -> Self {
        let r = &g.residual[k];
        let load: f64 = g.grf[k].iter().map(|f| f[g.up]).sum();
        let whole = measured || load <= 1e-9;
        let cop = if whole {
            *pelvis
        } else {
            g.grf[k]
                .iter()
                .zip(&g.cop[k])
                .map(|(f, c)| c * f[g.up])
                .sum::<Vector3<f64>>()
                / load
        };
        Self {
            whole,
            moment_clamped: Vector3::new(r[3], r[4], r[5]).norm() > MET * weight * height,
            force_clamped: Vector3::new(r[0], r[1], r[2]).norm() > MET * weight,
            lever: cop - pelvis,
            height,
        }
    }

    fn apply(&self, dn: Vector3<f64>, df: Vector3<f64>) -> [f64; 6] {
        let (n, f) = if self.whole {
            (dn, df)
        } else {
            let zero = Vector3::zeros();
            let n = if self.moment_clamped {
                dn - self.lever.cross(&df)
            } else {
                zero
            };
            (n, if self.force_clamped { df } else { zero })
        };
        let h = self.height;
        [n.x, n.y, n.z, h * f.x, h * f.y, h * f.z]
    }
}

/// The most columns a frame's Jacobian has: the trunk's, four spline basis functions per
/// pelvis axis (two offsets, three rotations), the mass.
const FRAME_COLUMNS: usize = NT + 4 * (2 + 3) + 1;

/// One frame's Jacobian: its columns' indices in `x` and their entries (`[n; h f]`), the
/// first `len` of each; fixed arrays, so a take's frames are one allocation.
#[derive(Clone, Copy)]
struct Local {
    len: usize,
    cols: [usize; FRAME_COLUMNS],
    jac: [[f64; 6]; FRAME_COLUMNS],
}

impl Local {
    const EMPTY: Self = Self {
        len: 0,
        cols: [0; FRAME_COLUMNS],
        jac: [[0.0; 6]; FRAME_COLUMNS],
    };

    fn clear(&mut self) {
        self.len = 0;
    }

    fn push(&mut self, col: usize, entries: [f64; 6]) {
        self.cols[self.len] = col;
        self.jac[self.len] = entries;
        self.len += 1;
    }

    /// `JᵀJ += JₖᵀJₖ`, `Jᵀr += Jₖᵀrₖ`.
    fn accumulate(&self, rk: &[f64; 6], jtj: &mut DMatrix<f64>, jtr: &mut DVector<f64>) {
        let dot = |a: &[f64; 6], b: &[f64; 6]| (0..6).map(|r| a[r] * b[r]).sum::<f64>();
        let (cols, jac) = (&self.cols[..self.len], &self.jac[..self.len]);
        for (n, (a, ja)) in cols.iter().zip(jac).enumerate() {
            jtr[*a] += dot(ja, rk);
            jtj[(*a, *a)] += dot(ja, ja);
            // `dot(ja, jb) == dot(jb, ja)` to the bit (products commute): made once for both
            for (b, jb) in cols[..n].iter().zip(jac) {
                let d = dot(ja, jb);
                jtj[(*a, *b)] += d;
                jtj[(*b, *a)] += d;
            }
        }
    }
}

/// What every frame's Jacobian shares, computed once per normal equations.
struct Shared {
    layout: Layout,
    /// The mass scale (1: not adjusted).
    mass_scale: f64,
    /// The adjusted model's total mass (kg) and weight (N).
    mass: f64,
    weight: f64,
    /// Whether the ground reactions are measured.
    measured: bool,
    /// The last root-level body: the poses through it are all the root's wrench reads
    /// after RNEA (`last_root_level_body`).
    root_level: usize,
}

/// Scratch for one frame's finite differences, allocated once per normal equations.
struct Scratch {
    ws: Workspace,
    q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
}

impl Problem<'_> {
    /// What every frame's Jacobian at `x` (evaluated as `e`) shares.
    fn shared(&self, x: &DVector<f64>, e: &Evaluated) -> Shared {
        let mass = e.model.total_mass();
        Shared {
            layout: self.layout(),
            mass_scale: self.mass_scale(x),
            mass,
            weight: mass * e.model.gravity.norm(),
            measured: matches!(self.ground, Ground::Measured(_)),
            root_level: last_root_level_body(&e.model),
        }
    }

    /// The Gauss–Newton normal equations `JᵀJ`, `Jᵀr` at `x` (evaluated as `e`): per counted
    /// frame, the residual `r = [n; h f]` and how each parameter changes it (module doc).
    pub fn normal_equations(
        &self,
        x: &DVector<f64>,
        e: &Evaluated,
    ) -> (DMatrix<f64>, DVector<f64>) {
        let shared = self.shared(x, e);
        let np = shared.layout.len;
        let (mut jtj, mut jtr) = (DMatrix::zeros(np, np), DVector::zeros(np));
        let offset = self.trunk_offset(x);
        let s = shared.mass_scale;
        let moved: Vec<Model> = self
            .trunk
            .across
            .iter()
            .map(|u| {
                let m =
                    with_trunk_offset(self.model, self.trunk.bodies, &(offset + u * TRUNK_STEP));
                if s == 1.0 { m } else { with_mass_scale(&m, s) }
            })
            .collect();
        // each counted frame's Jacobian, frames in parallel (each computes the same operations
        // whatever thread runs it), then summed in frame order: the same bits on any number
        // of threads (`crate::par`)
        let frames: Vec<usize> = (0..e.q.len()).filter(|&k| self.counted[k]).collect();
        let mut locals: Vec<(usize, Local)> = frames.iter().map(|&k| (k, Local::EMPTY)).collect();
        let mut scratch = crate::par::scratch(|| {
            (
                Workspace::new(&e.model),
                Scratch {
                    ws: Workspace::new(&e.model),
                    q: vec![0.0; e.model.nq],
                    v: vec![0.0; e.model.nv],
                    a: vec![0.0; e.model.nv],
                },
            )
        });
        crate::par::for_each_block(
            &mut locals,
            crate::par::even_block(frames.len()),
            &mut scratch,
            |(ws, scratch), _, block| {
                for (k, local) in block.iter_mut() {
                    self.frame_jacobian(&shared, e, *k, &moved, ws, scratch, local);
                }
            },
        );
        for (k, local) in &locals {
            let rk = self.weighted(&e.ground.residual[*k]);
            local.accumulate(&rk, &mut jtj, &mut jtr);
        }
        (jtj, jtr)
    }

    /// Frame `k`'s Jacobian into `local` (`moved`: the models with the trunk offset moved
    /// along each direction by [`TRUNK_STEP`]).
    #[allow(clippy::too_many_arguments)]
    fn frame_jacobian(
        &self,
        shared: &Shared,
        e: &Evaluated,
        k: usize,
        moved: &[Model],
        ws: &mut Workspace,
        scratch: &mut Scratch,
        local: &mut Local,
    ) {
        let layout = &shared.layout;
        local.clear();
        let relative = self.relative.get().and_then(Option::as_ref);
        let qva = [&e.q[k][..], &e.v[k], &e.a[k]];
        let needed = e.ground.wrench[k];
        let rotation = layout.rotation.zip(self.rotation.as_ref());
        let trunk = !self.trunk.bodies.is_empty();
        // the frame's whole-body terms and root motion, when a column reads them (the same
        // for every trunk offset: the kinematics are the model's); the centre of mass and the
        // pelvis are the evaluation's own (the same terms made them)
        let terms = relative.filter(|_| trunk || rotation.is_some()).map(|r| {
            let c = r.composite(k, &e.model, shared.mass_scale);
            let root = r.root_motion(&e.model, qva[0], qva[1], qva[2], ws);
            (r, c, root, ws.o_x_i[self.root])
        });
        let (com, pelvis, rot) = match relative {
            Some(_) => (
                e.ground.com[k],
                e.ground.pelvis[k],
                terms.as_ref().map_or(Matrix3::identity(), |t| t.3.rot),
            ),
            None => {
                forward_kinematics(&e.model, ws, &e.q[k]);
                let x = ws.o_x_i[self.root];
                (centre_of_mass(&e.model, ws), x.trans, x.rot)
            }
        };
        let pass = Pass::new(
            &e.ground,
            k,
            &pelvis,
            self.height,
            shared.measured,
            shared.weight,
        );
        // trunk: finite differences of the needed wrench (without trunk bodies the moved
        // models are the evaluated one, and the columns zero)
        for (j, m) in moved.iter().enumerate() {
            let w = match (&terms, relative) {
                _ if !trunk && relative.is_some() => needed,
                (Some((r, c, root, o_x_p)), _) => about(
                    &r.wrench_at(&r.with_trunk_of(c, k, m), root, o_x_p),
                    &pelvis,
                ),
                _ => about(&rnea_wrench(m, shared, qva, &mut scratch.ws), &pelvis),
            };
            let d: [f64; 6] = std::array::from_fn(|c| (w[c] - needed[c]) / TRUNK_STEP);
            local.push(j, pass.apply(v3(&d, 3), v3(&d, 0)));
        }
        self.pelvis_columns(shared, &com, &pelvis, &e.ground, k, &pass, local);
        if let Some((at, r)) = rotation {
            let terms = terms.as_ref().map(|(r, c, _, _)| (*r, c));
            self.rotation_columns(
                e, k, at, r, &rot, &pelvis, &pass, shared, terms, scratch, local,
            );
        }
        if let Some(at) = layout.mass {
            // the needed wrench is linear in the inertial parameters
            let d: [f64; 6] = std::array::from_fn(|c| needed[c] / shared.mass_scale);
            local.push(at, pass.apply(v3(&d, 3), v3(&d, 0)));
        }
    }

    /// The pelvis spline's columns of frame `k`'s Jacobian: a rigid translation adds the force
    /// `M δp̈` at the centre of mass (`ws` at frame `k`); against measured forces, which stay
    /// where they act, the pelvis's move `δp` adds `δp × F` to the residual moment about it.
    #[allow(clippy::too_many_arguments)]
    fn pelvis_columns(
        &self,
        shared: &Shared,
        com: &Vector3<f64>,
        pelvis: &Vector3<f64>,
        g: &GroundReactions,
        k: usize,
        pass: &Pass,
        local: &mut Local,
    ) {
        let nb = self.spline.len();
        let (at, mass, measured) = (shared.layout.translation, shared.mass, shared.measured);
        let lever = com - pelvis;
        let applied: Vector3<f64> = g.grf[k].iter().sum();
        let (i0, b) = self.spline.basis(self.motion.time[k]);
        for (h, axis) in self.horizontal().into_iter().enumerate() {
            for (j, (value, acc)) in b[0].iter().zip(&b[2]).enumerate() {
                let df = Vector3::ith(axis, mass * acc);
                let mut dn = lever.cross(&df);
                if measured {
                    dn += Vector3::ith(axis, *value).cross(&applied);
                }
                local.push(at + h * nb + i0 + j, pass.apply(dn, df));
            }
        }
    }

    /// The pelvis rotation's columns of frame `k`'s Jacobian: the needed wrench's change with
    /// a rotation of the whole body about the pelvis, its rate and acceleration along each
    /// world axis (finite differences of inverse dynamics), chained with the spline's basis.
    #[allow(clippy::too_many_arguments)]
    fn rotation_columns(
        &self,
        e: &Evaluated,
        k: usize,
        at: usize,
        r: &RootRotation,
        rot: &Matrix3<f64>,
        pelvis: &Vector3<f64>,
        pass: &Pass,
        shared: &Shared,
        terms: Option<(&RootRelative, &Composite)>,
        scratch: &mut Scratch,
        local: &mut Local,
    ) {
        let nb = self.spline.len();
        let needed = e.ground.wrench[k];
        let (i0, b) = self.spline.basis(self.motion.time[k]);
        for axis in 0..3 {
            let mut d = [[0.0; 6]; 3];
            for (order, dk) in d.iter_mut().enumerate() {
                let e_axis = Vector3::ith(axis, ROTATION_STEP);
                let turn = match order {
                    0 => BodyRotation::exp(&e_axis, &Vector3::zeros(), &Vector3::zeros()),
                    1 => BodyRotation::exp(&Vector3::zeros(), &e_axis, &Vector3::zeros()),
                    _ => BodyRotation::exp(&Vector3::zeros(), &Vector3::zeros(), &e_axis),
                };
                scratch.q.copy_from_slice(&e.q[k]);
                scratch.v.copy_from_slice(&e.v[k]);
                scratch.a.copy_from_slice(&e.a[k]);
                if !rotate_root(
                    r,
                    rot,
                    &turn,
                    &mut scratch.q,
                    &mut scratch.v,
                    &mut scratch.a,
                ) {
                    continue;
                }
                let (sw, qva) = (&mut scratch.ws, [&scratch.q[..], &scratch.v, &scratch.a]);
                let w = match terms {
                    Some((r, c)) => r.wrench(c, &e.model, qva, sw),
                    None => rnea_wrench(&e.model, shared, qva, sw),
                };
                let w = about(&w, pelvis);
                *dk = std::array::from_fn(|c| (w[c] - needed[c]) / ROTATION_STEP);
            }
            for j in 0..4usize {
                let col: [f64; 6] =
                    std::array::from_fn(|c| d.iter().zip(&b).map(|(dk, bk)| dk[c] * bk[j]).sum());
                let entries = pass.apply(v3(&col, 3), v3(&col, 0));
                local.push(at + axis * nb + i0 + j, entries);
            }
        }
    }
}

/// The wrench `model` needs over the state `qva` by kinematics through the root-level bodies
/// and RNEA (world axes, about the world origin): what the root-relative terms stand in for.
fn rnea_wrench(
    model: &Model,
    shared: &Shared,
    [q, v, a]: [&[f64]; 3],
    ws: &mut Workspace,
) -> ForceVec {
    forward_kinematics_through(model, ws, q, shared.root_level);
    rnea(model, ws, q, v, a, None);
    root_wrench(model, ws)
}

fn v3(w: &[f64; 6], at: usize) -> Vector3<f64> {
    Vector3::new(w[at], w[at + 1], w[at + 2])
}

#[cfg(test)]
mod tests {
    //! Against measured forces the residual is linear in the adjustments to first order and no
    //! clamp intervenes: the Jacobian's prediction of a small step must equal the change that
    //! evaluating the step gives (pelvis offset, rotation and mass).
    use super::super::root::{root_rotation, root_translation};
    use super::super::{Motion, Trunk};
    use super::*;
    use crate::dynamics::grf::measured::FootLoads;
    use crate::dynamics::samples::{SplitMix64, random_configuration, random_tree, random_vector};
    use crate::motion::spline::UniformBSpline;

    #[test]
    fn the_jacobian_predicts_a_small_step_against_measured_forces() {
        let model = random_tree(9, 21, true);
        let mut rng = SplitMix64(5);
        let n = 12;
        let time: Vec<f64> = (0..n).map(|k| 0.05 * k as f64).collect();
        let (mut q, mut v, mut a) = (vec![], vec![], vec![]);
        for _ in 0..n {
            let (mut qk, mut vk, mut ak) = (
                vec![0.0; model.nq],
                vec![0.0; model.nv],
                vec![0.0; model.nv],
            );
            random_configuration(&model, &mut rng, &mut qk);
            random_vector(&mut rng, 1.0, &mut vk);
            random_vector(&mut rng, 1.0, &mut ak);
            q.push(qk);
            v.push(vk);
            a.push(ak);
        }
        let loads = FootLoads {
            feet: vec!["left".into()],
            bodies: vec![3],
            force: (0..n).map(|_| vec![rng.vec3(200.0)]).collect(),
            cop: (0..n).map(|_| vec![rng.vec3(0.5)]).collect(),
            free_moment: (0..n).map(|_| vec![rng.range(-5.0, 5.0)]).collect(),
        };
        let counted = vec![true; n];
        let problem = Problem {
            model: &model,
            ground: Ground::Measured(&loads),
            trunk: Trunk {
                bodies: &[],
                across: [Vector3::zeros(); 2],
            },
            motion: Motion {
                time: &time,
                q: &q,
                v: &v,
                a: &a,
            },
            up: 2,
            counted: &counted,
            spline: UniformBSpline::new(0.0, time[n - 1], 0.15).unwrap(),
            translation: root_translation(&model).unwrap(),
            rotation: root_rotation(&model),
            root: 1,
            height: 1.0,
            base_pelvis: &[],
            free: None,
            relative: Default::default(),
            reuse: Default::default(),
        };
        let layout = problem.layout();
        assert!(layout.rotation.is_some() && layout.mass.is_some());
        let x0 = DVector::zeros(layout.len);
        let e0 = problem.evaluate(&x0).unwrap();
        let mut dx = DVector::zeros(layout.len);
        for i in NT..layout.len {
            dx[i] = rng.range(-1e-5, 1e-5);
        }
        let e1 = problem.evaluate(&dx).unwrap();
        let mut ws = Workspace::new(&e0.model);
        let mut scratch = Scratch {
            ws: Workspace::new(&e0.model),
            q: vec![0.0; model.nq],
            v: vec![0.0; model.nv],
            a: vec![0.0; model.nv],
        };
        let mut local = Local::EMPTY;
        let shared = problem.shared(&x0, &e0);
        for k in 0..n {
            problem.frame_jacobian(&shared, &e0, k, &[], &mut ws, &mut scratch, &mut local);
            let (r0, r1) = (
                problem.weighted(&e0.ground.residual[k]),
                problem.weighted(&e1.ground.residual[k]),
            );
            for row in 0..6 {
                let predicted: f64 = local.cols[..local.len]
                    .iter()
                    .zip(&local.jac[..local.len])
                    .map(|(c, j)| j[row] * dx[*c])
                    .sum();
                let actual = r1[row] - r0[row];
                assert!(
                    (predicted - actual).abs() <= 1e-3 * actual.abs().max(1e-4),
                    "frame {k} row {row}: predicted {predicted:e}, actual {actual:e}"
                );
            }
        }
    }
}
