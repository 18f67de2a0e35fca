//! The whole body's motion relative to its root, once per take, so that each trial of residual
//! reduction gets its needed wrenches, centre of mass and foot poses without the frames'
//! kinematics and inverse dynamics.
//!
//! Residual reduction moves only the root (the pelvis offset and rotation), the trunk's mass
//! centre and the mass scale; every other body keeps its motion relative to the root. Write
//! the whole-body Newton–Euler equation in the root body `P`'s frame (Featherstone 2008,
//! §2.13 and §9.4; the centroidal form of Orin, Goswami & Lee 2013, "Centroidal dynamics of a
//! humanoid robot", *Auton. Robots* 35): with `Xᵢ = ᴾXᵢ` (body i in P's frame) and the body's
//! velocity relative to the root `vᵢʳ` (body coordinates; its acceleration `aᵢʳ`), every body
//! moves with `vᵢ = Xᵢ⁻¹ v_P + vᵢʳ` and `aᵢ = Xᵢ⁻¹ a_P + aᵢʳ + (Xᵢ⁻¹ v_P) × vᵢʳ`, so the wrench
//! the root needs, `f_P = Σ Xᵢ* (Iᵢ aᵢ + vᵢ ×* Iᵢ vᵢ)`, is
//!
//! `f_P = I_C a_P + İ_C v_P + v_P ×* (I_C v_P + h) + ḣ`,
//!
//! `I_C = Σ Xᵢ* Iᵢ Xᵢ⁻¹` (the composite inertia in P's frame), `İ_C = Σ (ṽᵢ ×* Ĩᵢ − Ĩᵢ ṽᵢ×)`
//! its rate (`ṽᵢ`, `Ĩᵢ`: the relative velocity and inertia in P's frame), `h = Σ Xᵢ* Iᵢ vᵢʳ`
//! the relative momentum and `ḣ = Σ Xᵢ* (Iᵢ aᵢʳ + vᵢʳ ×* Iᵢ vᵢʳ)` its rate: each a function of
//! the relative motion alone, computed once per frame here, with `a_P` the root's acceleration
//! against gravity (RNEA's `a₀ = −g`). The trunk's bodies, whose inertia a trial moves, are kept
//! apart (their `Xᵢ`, `vᵢʳ`, `aᵢʳ`) and added with the trial's inertia; the mass scale
//! multiplies the rest (the equation is linear in the inertias). The same numbers as RNEA's to
//! rounding (`tests/residual_reduction.rs`).

use crate::dynamics::grf::NeededWrenches;
use crate::dynamics::rnea::rnea_terms;
use crate::dynamics::{Workspace, forward_kinematics};
use crate::model::Model;
use crate::spatial::{ForceVec, MotionVec, SpatialInertia, SpatialTransform};
use nalgebra::{Matrix3, Matrix6, Vector3};

/// One frame's terms of the bodies other than the trunk's, in P's frame.
#[derive(Clone, Copy)]
struct Rest {
    /// `I_C` as a 6×6 matrix (angular first).
    inertia: Matrix6<f64>,
    /// `İ_C`.
    inertia_rate: Matrix6<f64>,
    /// `h` and `ḣ`.
    momentum: ForceVec,
    momentum_rate: ForceVec,
    /// `Σ mᵢ cᵢ` (kg·m, P's frame) and `Σ mᵢ`.
    first_moment: Vector3<f64>,
    mass: f64,
}

impl Rest {
    fn zero() -> Self {
        Self {
            inertia: Matrix6::zeros(),
            inertia_rate: Matrix6::zeros(),
            momentum: ForceVec::ZERO,
            momentum_rate: ForceVec::ZERO,
            first_moment: Vector3::zeros(),
            mass: 0.0,
        }
    }

    /// Adds a body of inertia `inertia` at `x` (`ᴾXᵢ`) moving relative to the root with `v`,
    /// `a` (its frame).
    fn add(
        &mut self,
        inertia: &SpatialInertia,
        x: &SpatialTransform,
        v: &MotionVec,
        a: &MotionVec,
    ) {
        let m = inertia.transformed(x).to_matrix();
        let c = crm(&x.act_motion(v));
        self.inertia += m;
        self.inertia_rate -= c.transpose() * m + m * c;
        let (h, dh) = body_momentum(inertia, v, a);
        self.momentum += x.act_force(&h);
        self.momentum_rate += x.act_force(&dh);
        self.first_moment += x.transform_point(&inertia.com) * inertia.mass;
        self.mass += inertia.mass;
    }
}

/// One frame's motion of one trunk body relative to the root.
#[derive(Clone, Copy)]
struct Kept {
    /// `ᴾXᵢ`.
    pose: SpatialTransform,
    v: MotionVec,
    a: MotionVec,
    /// The body's rotational inertia about its mass centre in P's axes, `R Ic Rᵀ`
    /// ([`SpatialInertia::transformed`]'s), for the terms' own inertia `trunk_ic`: a trial
    /// moves the trunk's mass centres, not their rotational inertias, so it is made once;
    /// likewise `Ic ω` and `Ic ω̇` of the relative motion (body frame), and the relative
    /// velocity in P's frame.
    rotated_ic: Matrix3<f64>,
    ic_v: Vector3<f64>,
    ic_a: Vector3<f64>,
    v_p: MotionVec,
}

impl Kept {
    fn new(pose: SpatialTransform, v: MotionVec, a: MotionVec, inertia: &SpatialInertia) -> Self {
        Self {
            pose,
            v,
            a,
            rotated_ic: inertia.transformed(&pose).inertia_com,
            ic_v: inertia.inertia_com * v.ang,
            ic_a: inertia.inertia_com * a.ang,
            v_p: pose.act_motion(&v),
        }
    }
}

/// The root-relative terms of a take (module doc), for the bodies the estimate keeps
/// ([`crate::dynamics::grf::kept_bodies`]) and the trunk's.
pub(super) struct RootRelative {
    /// The root body P and its ancestors (the root's joints), P last.
    chain: Vec<usize>,
    /// Kept bodies, and per frame their poses relative to P (`[frame * kept.len() + j]`;
    /// the chain's own poses come from the trial's kinematics).
    kept: Vec<usize>,
    kept_poses: Vec<SpatialTransform>,
    trunk: Vec<usize>,
    /// Per trunk body: its rotational inertia about its mass centre (body frame) in the model
    /// the terms were made for; a trial whose inertia differs makes `R Ic Rᵀ` itself.
    trunk_ic: Vec<Matrix3<f64>>,
    /// `[frame * trunk.len() + j]`.
    trunk_motion: Vec<Kept>,
    rest: Vec<Rest>,
}

/// The root body `root` and its ancestors (the root's joints), ascending, when they carry no
/// mass but the root's own and every other body hangs below the root; `None` otherwise.
fn root_chain(model: &Model, root: usize) -> Option<Vec<usize>> {
    let mut chain = vec![root];
    while let Some(&b) = chain.last().filter(|&&b| model.parent[b] != 0) {
        chain.push(model.parent[b]);
    }
    chain.reverse();
    let below_root = |mut i: usize| {
        while i > root {
            i = model.parent[i];
        }
        i == root
    };
    let massless = chain[..chain.len() - 1]
        .iter()
        .all(|&b| model.inertia[b].is_zero());
    let hung = (1..model.nbodies()).all(|i| chain.binary_search(&i).is_ok() || below_root(i));
    (massless && hung).then_some(chain)
}

/// One frame's terms ([`RootRelative::new`]) from `ws`, posed by forward kinematics and
/// moved by RNEA's forward pass with the root's joints still: the `kept` bodies' poses
/// relative to the root (identity on the root's `chain`), the `trunk` bodies' motion, and the
/// rest's sums.
fn frame_terms(
    model: &Model,
    ws: &Workspace,
    (kept, trunk, chain): (&[usize], &[usize], &[usize]),
    (kept_poses, trunk_motion, rest): (&mut [SpatialTransform], &mut [Kept], &mut Rest),
) {
    let root = *chain.last().expect("the root");
    let in_chain = |i: usize| chain.binary_search(&i).is_ok();
    let p_x_0 = ws.o_x_i[root].inverse();
    let relative = |i: usize| p_x_0.compose(&ws.o_x_i[i]);
    for (x, &b) in kept_poses.iter_mut().zip(kept) {
        *x = if in_chain(b) {
            SpatialTransform::IDENTITY
        } else {
            relative(b)
        };
    }
    for i in (1..model.nbodies()).filter(|&i| !in_chain(i) || i == root) {
        let x = relative(i);
        if let Some(j) = trunk.iter().position(|&b| b == i) {
            trunk_motion[j] = Kept::new(x, ws.v[i], ws.a[i], &model.inertia[i]);
            continue;
        }
        if !model.inertia[i].is_zero() {
            rest.add(&model.inertia[i], &x, &ws.v[i], &ws.a[i]);
        }
    }
}

/// `v` (`n · m` items) as `n` rows of `m` (empty rows when `m` is 0).
fn rows<T>(v: &mut [T], n: usize, m: usize) -> Vec<&mut [T]> {
    if m == 0 {
        return (0..n).map(|_| &mut [][..]).collect();
    }
    v.chunks_mut(m).collect()
}

/// `crm(m)`: the 6×6 matrix of `m ×ₘ` (Featherstone eq. 2.31).
fn crm(m: &MotionVec) -> Matrix6<f64> {
    let (w, v) = (crate::spatial::skew(&m.ang), crate::spatial::skew(&m.lin));
    let mut x = Matrix6::zeros();
    x.fixed_view_mut::<3, 3>(0, 0).copy_from(&w);
    x.fixed_view_mut::<3, 3>(3, 3).copy_from(&w);
    x.fixed_view_mut::<3, 3>(3, 0).copy_from(&v);
    x
}

/// `I m` for a 6×6 inertia-like matrix (angular first).
fn times(i: &Matrix6<f64>, m: &MotionVec) -> ForceVec {
    ForceVec::from_vector6(&(i * m.to_vector6()))
}

/// A body's own terms `(I m, I a + v ×* I v)` in its frame.
fn body_momentum(i: &SpatialInertia, v: &MotionVec, a: &MotionVec) -> (ForceVec, ForceVec) {
    let h = i.mul_motion(v);
    (h, i.mul_motion(a) + v.cross_force(&h))
}

impl RootRelative {
    /// The terms of `model` (the unadjusted one) over the motion `q`, `v`, `a` with root body
    /// `root`: `None` when the root's joints carry mass, a body hangs elsewhere than below the
    /// root, or the trunk has more than [`MAX_TRUNK`] bodies (then trials run the whole
    /// kinematics and RNEA).
    pub fn new(
        model: &Model,
        root: usize,
        kept: Vec<usize>,
        trunk: &[usize],
        [q, v, a]: [&[Vec<f64>]; 3],
    ) -> Option<Self> {
        if trunk.len() > MAX_TRUNK {
            return None;
        }
        let chain = root_chain(model, root)?;
        let on_chain = chain.clone();
        let chain_dofs: Vec<usize> = chain
            .iter()
            .flat_map(|&b| model.idx_v[b]..model.idx_v[b] + model.joints[b].nv())
            .collect();
        let nt = trunk.len();
        let mut out = Self {
            kept_poses: vec![SpatialTransform::IDENTITY; q.len() * kept.len()],
            trunk_motion: vec![
                Kept::new(
                    SpatialTransform::IDENTITY,
                    MotionVec::ZERO,
                    MotionVec::ZERO,
                    &SpatialInertia::ZERO,
                );
                q.len() * trunk.len()
            ],
            rest: vec![Rest::zero(); q.len()],
            chain,
            kept,
            trunk: trunk.to_vec(),
            trunk_ic: trunk
                .iter()
                .map(|&b| model.inertia[b].inertia_com)
                .collect(),
        };
        // frames in parallel, each computing what it would alone (`crate::par`)
        let (n, nk) = (q.len(), out.kept.len());
        let (kept, trunk_of) = (&out.kept, &out.trunk);
        let mut frames: Vec<_> = rows(&mut out.kept_poses, n, nk)
            .into_iter()
            .zip(rows(&mut out.trunk_motion, n, nt))
            .zip(out.rest.iter_mut())
            .map(|((x, t), r)| (x, t, r))
            .collect();
        crate::par::for_each_block(
            &mut frames,
            crate::par::even_block(n),
            &mut crate::par::scratch(|| {
                (
                    Workspace::new(model),
                    vec![0.0; model.nv],
                    vec![0.0; model.nv],
                )
            }),
            |(ws, vr, ar), first, block| {
                for (i, (kept_poses, trunk_motion, rest)) in block.iter_mut().enumerate() {
                    let k = first + i;
                    forward_kinematics(model, ws, &q[k]);
                    // the motion with the root's joints still: each body's velocity and
                    // acceleration relative to the root, in its own frame
                    vr.copy_from_slice(&v[k]);
                    ar.copy_from_slice(&a[k]);
                    for &d in &chain_dofs {
                        (vr[d], ar[d]) = (0.0, 0.0);
                    }
                    rnea_terms(model, ws, &q[k], Some(vr), Some(ar), None, false);
                    let parts = (&kept[..], &trunk_of[..], &on_chain[..]);
                    frame_terms(model, ws, parts, (kept_poses, trunk_motion, rest));
                }
            },
        );
        drop(frames);
        Some(out)
    }

    /// Pass 1 of the ground-reaction estimate for a trial: `model` (the trial's: the trunk's
    /// inertia moved, every mass scaled by `scale`) over the motion `q`, `v`, `a` (the trial's:
    /// only the root's coordinates differ from the take's), from the kept terms.
    pub fn needed(&self, model: &Model, scale: f64, [q, v, a]: [&[Vec<f64>]; 3]) -> NeededWrenches {
        let n = q.len();
        let root = self.root();
        let nk = self.kept.len();
        let mut out = NeededWrenches {
            needed: vec![ForceVec::ZERO; n],
            com: vec![Vector3::zeros(); n],
            poses: vec![SpatialTransform::IDENTITY; n * nk],
        };
        // frames in parallel, each computing what it would alone (`crate::par`)
        let mut frames: Vec<_> = out
            .needed
            .iter_mut()
            .zip(out.com.iter_mut())
            .zip(rows(&mut out.poses, n, nk))
            .map(|((w, c), x)| (w, c, x))
            .collect();
        crate::par::for_each_block(
            &mut frames,
            crate::par::even_block(n),
            &mut crate::par::scratch(|| Workspace::new(model)),
            |ws, first, block| {
                for (i, (w, c, x)) in block.iter_mut().enumerate() {
                    let k = first + i;
                    (**w, **c) = self.frame(k, model, scale, [&q[k], &v[k], &a[k]], ws);
                    let o_x_p = ws.o_x_i[root];
                    for ((x, &b), kept) in
                        x.iter_mut().zip(&self.kept).zip(&self.kept_poses[k * nk..])
                    {
                        *x = if self.chain.contains(&b) {
                            ws.o_x_i[b]
                        } else {
                            o_x_p.compose(kept)
                        };
                    }
                }
            },
        );
        drop(frames);
        out
    }

    /// The root body P.
    pub fn root(&self) -> usize {
        *self.chain.last().expect("the root")
    }

    /// Frame `k` of a trial ([`RootRelative::needed`]): the wrench the whole body needs (world
    /// axes, about the world origin, as RNEA's `root_wrench`) and its centre of mass (m,
    /// world). Writes the world poses of the root and its joints' bodies into `ws.o_x_i`.
    pub fn frame(
        &self,
        k: usize,
        model: &Model,
        scale: f64,
        qva: [&[f64]; 3],
        ws: &mut Workspace,
    ) -> (ForceVec, Vector3<f64>) {
        let c = self.composite(k, model, scale);
        let w = self.wrench(&c, model, qva, ws);
        (w, ws.o_x_i[self.root()].transform_point(&c.com))
    }

    /// Frame `k`'s whole-body terms for `model` (its trunk's inertia, the rest's scaled by
    /// `scale`): what [`RootRelative::wrench`] needs for any motion of the root.
    pub fn composite(&self, k: usize, model: &Model, scale: f64) -> Composite {
        let rest = &self.rest[k];
        // `x * 1.0 == x` for every float: the unscaled rest is copied as it is
        let scaled = |m: &Matrix6<f64>| if scale == 1.0 { *m } else { m * scale };
        let (momentum, momentum_rate, first_moment, mass) = if scale == 1.0 {
            (
                rest.momentum,
                rest.momentum_rate,
                rest.first_moment,
                rest.mass,
            )
        } else {
            (
                rest.momentum * scale,
                rest.momentum_rate * scale,
                rest.first_moment * scale,
                rest.mass * scale,
            )
        };
        let mut c = Composite {
            rest: scaled(&rest.inertia),
            rest_rate: scaled(&rest.inertia_rate),
            trunk: [(SpatialInertia::ZERO, MotionVec::ZERO); MAX_TRUNK],
            trunk_len: self.trunk.len(),
            rest_momentum: [momentum, momentum_rate],
            rest_first_moment: first_moment,
            rest_mass: mass,
            momentum,
            momentum_rate,
            com: Vector3::zeros(),
        };
        self.add_trunk(k, model, &mut c);
        c
    }

    /// Frame `k`'s whole-body terms for `model`, whose bodies other than the trunk's are
    /// those `base` was made for ([`RootRelative::composite`] of another trunk inertia, at the
    /// same mass scale): `base`'s rest and `model`'s trunk, the same bits as
    /// [`RootRelative::composite`] of `model`.
    pub fn with_trunk_of(&self, base: &Composite, k: usize, model: &Model) -> Composite {
        let mut c = Composite {
            trunk: [(SpatialInertia::ZERO, MotionVec::ZERO); MAX_TRUNK],
            momentum: base.rest_momentum[0],
            momentum_rate: base.rest_momentum[1],
            com: Vector3::zeros(),
            ..*base
        };
        self.add_trunk(k, model, &mut c);
        c
    }

    /// Adds `model`'s trunk bodies at frame `k` to the terms `c` of the rest.
    fn add_trunk(&self, k: usize, model: &Model, c: &mut Composite) {
        let nt = self.trunk.len();
        let mut first_moment = c.rest_first_moment;
        let mut mass = c.rest_mass;
        for (j, &b) in self.trunk.iter().enumerate() {
            let t = &self.trunk_motion[k * nt + j];
            let inertia = model.inertia[b];
            // the body's inertia and relative velocity in P's frame, and its momentum and
            // rate (what depends on the rotational inertia alone kept when it is the terms'
            // own: the same operations, made once)
            let com = t.pose.transform_point(&inertia.com);
            let (ip, (h, dh)) = if inertia.inertia_com == self.trunk_ic[j] {
                let ip = SpatialInertia {
                    com,
                    inertia_com: t.rotated_ic,
                    ..inertia
                };
                let times = |m: &MotionVec, ic_m: &Vector3<f64>| {
                    // `SpatialInertia::mul_motion` with `Ic m.ang` given
                    let lin = (m.lin - inertia.com.cross(&m.ang)) * inertia.mass;
                    ForceVec {
                        ang: ic_m + inertia.com.cross(&lin),
                        lin,
                    }
                };
                let h = times(&t.v, &t.ic_v);
                (ip, (h, times(&t.a, &t.ic_a) + t.v.cross_force(&h)))
            } else {
                (
                    inertia.transformed(&t.pose),
                    body_momentum(&inertia, &t.v, &t.a),
                )
            };
            c.trunk[j] = (ip, t.v_p);
            c.momentum += t.pose.act_force(&h);
            c.momentum_rate += t.pose.act_force(&dh);
            first_moment += com * inertia.mass;
            mass += inertia.mass;
        }
        c.com = first_moment / mass.max(1e-12);
    }

    /// The wrench the whole body with terms `c` needs (world axes, about the world origin)
    /// when its root moves as the state `q`, `v`, `a` says (module doc); writes the world
    /// poses of the root and its joints' bodies into `ws.o_x_i`.
    pub fn wrench(
        &self,
        c: &Composite,
        model: &Model,
        [q, v, a]: [&[f64]; 3],
        ws: &mut Workspace,
    ) -> ForceVec {
        let root = self.root_motion(model, q, v, a, ws);
        self.wrench_at(c, &root, &ws.o_x_i[self.root()])
    }

    /// [`RootRelative::wrench`] for the root's motion `(v_P, a_P)` already found
    /// ([`RootRelative::root_motion`]), `o_x_p` the root's world pose: the same bits.
    pub fn wrench_at(
        &self,
        c: &Composite,
        &(vp, ap): &(MotionVec, MotionVec),
        o_x_p: &SpatialTransform,
    ) -> ForceVec {
        let mut inertia_v = times(&c.rest, &vp);
        let mut inertia_a = times(&c.rest, &ap);
        let mut rate_v = times(&c.rest_rate, &vp);
        for (ip, vt) in &c.trunk[..c.trunk_len] {
            let iv = ip.mul_motion(&vp);
            inertia_v += iv;
            inertia_a += ip.mul_motion(&ap);
            rate_v += vt.cross_force(&iv) - ip.mul_motion(&vt.cross_motion(&vp));
        }
        let f = inertia_a + rate_v + vp.cross_force(&(inertia_v + c.momentum)) + c.momentum_rate;
        o_x_p.act_force(&f)
    }

    /// The root body's velocity and acceleration against gravity (its frame) through the
    /// root's joints: `vᵢ = λXᵢ⁻¹ v_λ + Sᵢ q̇ᵢ`, `aᵢ = λXᵢ⁻¹ a_λ + Sᵢ q̈ᵢ + vᵢ × Sᵢ q̇ᵢ` from
    /// the world at rest accelerating at `−g` (RNEA's forward pass on the chain), and the
    /// chain's world poses into `ws.o_x_i` (`0Xᵢ = 0X_λ λXᵢ`).
    pub fn root_motion(
        &self,
        model: &Model,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        ws: &mut Workspace,
    ) -> (MotionVec, MotionVec) {
        let (mut vi, mut ai) = (
            MotionVec::ZERO,
            MotionVec::new(Vector3::zeros(), -model.gravity),
        );
        for &i in &self.chain {
            let x = model.parent_transform(i, q);
            ws.o_x_i[i] = ws.o_x_i[model.parent[i]].compose(&x.to_transform());
            let (j, iv) = (&model.joints[i], model.idx_v[i]);
            let (dq, ddq) = (&v[iv..iv + j.nv()], &a[iv..iv + j.nv()]);
            let s_dq = j.motion(dq);
            vi = x.act_inv_motion(&vi) + s_dq;
            ai = x.act_inv_motion(&ai) + j.motion(ddq) + vi.cross_motion(&s_dq);
        }
        (vi, ai)
    }
}

/// The most trunk bodies the terms keep apart (more: trials run the whole estimate).
const MAX_TRUNK: usize = 12;

/// One frame's whole-body terms for one model ([`RootRelative::composite`]), in P's frame:
/// the rest's `I_C` and `İ_C` (scaled), each trunk body's inertia and relative velocity, the
/// whole body's `h`, `ḣ` and centre of mass.
#[derive(Clone, Copy)]
pub(super) struct Composite {
    rest: Matrix6<f64>,
    rest_rate: Matrix6<f64>,
    trunk: [(SpatialInertia, MotionVec); MAX_TRUNK],
    trunk_len: usize,
    /// The rest's `h`, `ḣ` (scaled), first moment and mass: where the trunk's are added to.
    rest_momentum: [ForceVec; 2],
    rest_first_moment: Vector3<f64>,
    rest_mass: f64,
    momentum: ForceVec,
    momentum_rate: ForceVec,
    com: Vector3<f64>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::grf::root_wrench;
    use crate::dynamics::residual::{centre_of_mass, with_trunk_offset};
    use crate::dynamics::rnea;

    /// The demo walk loaded with `opts`, its floating root, every body kept, and its trunk
    /// (the `Spine` bodies, the last first).
    fn demo(
        opts: crate::pipeline::TakeOptions,
    ) -> (crate::pipeline::Take, usize, Vec<usize>, Vec<usize>) {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/demo_walk.bvh");
        let take = crate::pipeline::load_take(&path, &opts).unwrap();
        let model = &take.model;
        let root = crate::dynamics::grf::floating_root(model).unwrap();
        let kept: Vec<usize> = (1..model.nbodies()).collect();
        let trunk: Vec<usize> = (1..model.nbodies())
            .rev()
            .filter(|&i| model.body_names[i].starts_with("Spine"))
            .collect();
        (take, root, kept, trunk)
    }

    /// A trial's terms made from another trial's composite of the same frame
    /// ([`RootRelative::with_trunk_of`]), its wrench from a root motion found once
    /// ([`RootRelative::wrench_at`]), and the trunk's rotated inertias and `Ic ω` kept per
    /// frame are the bits of the whole composite and wrench, and of the trunk's inertias
    /// rotated anew (what the Jacobian's trunk differences computed before).
    #[test]
    fn the_terms_reused_across_trunk_offsets_are_the_same_bits() {
        let (take, root, kept, trunk) = demo(Default::default());
        let (model, s) = (&take.model, &take.states);
        let rel = RootRelative::new(model, root, kept.clone(), &trunk, [&s.q, &s.v, &s.a])
            .expect("terms");
        // the same terms, made to rotate every trunk inertia anew (NaN equals no inertia)
        let mut anew = RootRelative::new(model, root, kept, &trunk, [&s.q, &s.v, &s.a]).unwrap();
        anew.trunk_ic.fill(Matrix3::from_element(f64::NAN));
        let a = with_trunk_offset(model, &trunk, &Vector3::new(0.01, -0.02, 0.005));
        let b = with_trunk_offset(model, &trunk, &Vector3::new(0.015, -0.02, 0.005));
        let bits = |w: &ForceVec| w.to_vector6().map(f64::to_bits);
        let mut ws = Workspace::new(model);
        for k in 0..s.len() {
            let qva = [&s.q[k][..], &s.v[k], &s.a[k]];
            let whole = rel.composite(k, &b, 1.0);
            let w = rel.wrench(&whole, &b, qva, &mut ws);
            let reused = rel.with_trunk_of(&rel.composite(k, &a, 1.0), k, &b);
            let motion = rel.root_motion(&b, qva[0], qva[1], qva[2], &mut ws);
            let w_at = rel.wrench_at(&reused, &motion, &ws.o_x_i[root]);
            let w_anew = anew.wrench(&anew.composite(k, &b, 1.0), &b, qva, &mut ws);
            assert_eq!(bits(&w), bits(&w_at), "frame {k}: reused terms");
            assert_eq!(bits(&w), bits(&w_anew), "frame {k}: inertias rotated anew");
            assert_eq!(whole.com, reused.com, "frame {k}");
        }
    }

    /// The kept terms give what the whole kinematics and RNEA give, on the demo walk with the
    /// root moved, the trunk's inertia moved and the masses scaled, on both joint models.
    #[test]
    fn the_root_relative_terms_give_what_rnea_gives() {
        use crate::model::bvh::JointModel;
        for joints in [JointModel::Euler, JointModel::Ball] {
            let (take, root, kept, trunk) = demo(crate::pipeline::TakeOptions {
                joints,
                ..Default::default()
            });
            let (model, s) = (&take.model, &take.states);
            assert!(!trunk.is_empty());
            let rel = RootRelative::new(model, root, kept.clone(), &trunk, [&s.q, &s.v, &s.a])
                .expect("terms");
            // a trial: the root's coordinates moved, the trunk's mass centre, the masses
            let (mut q, mut v, mut a) = (s.q.clone(), s.v.clone(), s.a.clone());
            for k in 0..q.len() {
                let t = k as f64 * 0.01;
                for c in 0..6 {
                    q[k][c] += 0.02 * (t + c as f64).sin();
                    v[k][c] += 0.3 * (2.0 * t + c as f64).cos();
                    a[k][c] += 1.5 * (3.0 * t - c as f64).sin();
                }
            }
            let scale = 1.07;
            let mut trial = with_trunk_offset(model, &trunk, &Vector3::new(0.01, -0.02, 0.005));
            for i in trial.inertia.iter_mut() {
                *i = SpatialInertia::new(i.mass * scale, i.com, i.inertia_com * scale);
            }
            let got = rel.needed(&trial, scale, [&q, &v, &a]);
            let mut ws = Workspace::new(&trial);
            let (mut worst_f, mut worst_c, mut worst_x) = (0.0f64, 0.0f64, 0.0f64);
            for k in 0..q.len() {
                forward_kinematics(&trial, &mut ws, &q[k]);
                let com = centre_of_mass(&trial, &ws);
                for (j, &b) in kept.iter().enumerate() {
                    let (x, y) = (&got.poses[k * kept.len() + j], &ws.o_x_i[b]);
                    worst_x = worst_x
                        .max((x.rot - y.rot).amax())
                        .max((x.trans - y.trans).amax());
                }
                rnea(&trial, &mut ws, &q[k], &v[k], &a[k], None);
                let w = root_wrench(&trial, &ws);
                let d = (got.needed[k] - w).to_vector6().amax() / w.to_vector6().amax();
                worst_f = worst_f.max(d);
                worst_c = worst_c.max((got.com[k] - com).amax());
            }
            assert!(worst_f < 1e-11, "{joints:?}: wrench {worst_f:e}");
            assert!(worst_c < 1e-12, "{joints:?}: com {worst_c:e}");
            assert!(worst_x < 1e-12, "{joints:?}: poses {worst_x:e}");
        }
    }
}
