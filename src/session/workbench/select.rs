//! The selection: what a joint or coordinate name selects, the joint of a selection, and the
//! selection kept when results or takes change.

use super::super::SessionError;
use super::super::engine::{Analysis, Take, TakeData};
use super::{
    Workbench, anatomical_axis, best_coordinate, channel_by_range, coords_of_joint, err,
    is_anatomical, joint_of_name, joint_of_selection, names_a_joint,
};

/// The selection once results `r` are stored: `sel` if `r` has that coordinate; otherwise the
/// coordinate with the largest range of motion of the old selection's joint, or the first
/// rotation.
pub(super) fn selection_for(r: &Analysis, sel: Option<&str>) -> Option<String> {
    if let Some(s) = sel
        && (r.model.v_index(s).is_some() || is_anatomical(r, s))
    {
        return Some(s.to_string());
    }
    // a human take: its left knee's flexion, as a gait lab shows it first
    if sel.is_none()
        && let Some(c) = anatomical_axis(r, "knee_l")
    {
        return Some(c);
    }
    let joint = sel.and_then(|s| joint_of_name(&r.model, s));
    joint.and_then(|j| best_coordinate(r, &j)).or_else(|| {
        (0..r.model.nv)
            .find(|&k| r.model.is_angular(k))
            .map(|k| r.model.v_names[k].clone())
    })
}

/// The selection when `take` becomes active: `sel` if the take has it (a robot's coordinate,
/// or a coordinate of one of a BVH take's joints: `<joint>.<channel>`, `<joint>:<comp>`);
/// otherwise a robot's first rotation, or none for a take (its results choose).
pub(super) fn selection_on_load(take: &Take, sel: Option<&str>) -> Option<String> {
    match &take.data {
        TakeData::Robot(r) => sel
            .filter(|s| r.model.v_index(s).is_some())
            .map(str::to_string)
            .or_else(|| {
                (0..r.model.nv)
                    .find(|&k| r.model.is_angular(k))
                    .map(|k| r.model.v_names[k].clone())
            }),
        TakeData::Bvh(b) => sel.filter(|s| names_a_joint(b, s)).map(str::to_string),
    }
}

impl Workbench {
    /// The coordinates of a joint (a BVH joint, or a robot joint) in the latest results.
    /// The anatomical axes of the joint of `sel` when `sel` is one (`knee_l:flexion` →
    /// `knee_l:flexion`, `knee_l:adduction`, `knee_l:rotation`), for ←/→ in the TUI.
    pub fn anatomical_axes(&self, sel: &str) -> Option<Vec<String>> {
        let r = self.latest_results()?;
        if !is_anatomical(r, sel) {
            return None;
        }
        let joint = sel.split(':').next()?;
        Some(
            ["flexion", "adduction", "rotation"]
                .iter()
                .map(|a| format!("{joint}:{a}"))
                .filter(|c| is_anatomical(r, c))
                .collect(),
        )
    }

    /// The joint of the selection, as the joint tree names it: the BVH joint at an
    /// anatomical joint's centre (`knee_l:flexion` → `LeftLeg`), the joint of a coordinate
    /// (`LeftLeg.Xrotation`, `LeftLeg:wx`, a robot's `j2`).
    pub fn selected_joint(&self) -> Option<String> {
        let sel = self.selection.as_deref()?;
        if let Some(r) = self.latest_results()
            && is_anatomical(r, sel)
        {
            return joint_of_selection(r, sel);
        }
        let r = self.latest_results();
        r.and_then(|r| joint_of_name(&r.model, sel)).or_else(|| {
            // before results: the name up to the coordinate's separator
            let tree = self.take()?.joint_tree();
            tree.into_iter()
                .map(|(n, _)| n)
                .filter(|n| {
                    sel == n
                        || sel
                            .strip_prefix(n.as_str())
                            .is_some_and(|r| r.starts_with(['.', ':']))
                })
                .max_by_key(|n| n.len())
        })
    }

    pub fn joint_coords(&self, joint: &str) -> Vec<String> {
        match self.latest_results() {
            Some(r) => coords_of_joint(&r.model, joint),
            None => vec![],
        }
    }

    /// True when the latest results were computed for the model the current parameters
    /// build (same joint model, locks, subtree and joint translations): their coordinates are
    /// those of the next results.
    fn results_model_current(&self) -> bool {
        self.results.as_ref().is_some_and(|(_, p)| {
            let (a, b) = (&p.take, &self.params.take);
            a.joints == b.joints
                && a.lock == b.lock
                && a.subtree == b.subtree
                && a.joint_translations == b.joint_translations
        })
    }

    /// A coordinate name from a coordinate or a joint name. A joint gives its coordinate with
    /// the largest range of motion over the take (the knee's and elbow's flexion axis):
    /// from the latest results, or before any result from the BVH rotation channels (the
    /// channel's axis names the ball model's rotation-vector component, `J:wx` for
    /// `Xrotation`).
    pub(super) fn resolve_coord(&self, name: &str) -> Result<String, SessionError> {
        let take = self
            .take()
            .ok_or_else(|| err("no take loaded (load PATH first)"))?;
        // results of another model (computed before `set joints`, `lock`, `subtree`, …) name
        // coordinates the next results will not have: then choose from the take's channels
        let current = self
            .latest_results()
            .filter(|_| self.results_model_current());
        if let Some(r) = current
            && r.model.v_index(name).is_some()
        {
            return Ok(name.to_string());
        }
        if let Some(c) = self.latest_results().and_then(|r| anatomical_axis(r, name)) {
            return Ok(c);
        }
        if let Some(rb) = take.robot() {
            // a robot joint is its coordinate (or the first of a multi-DoF joint)
            return coords_of_joint(&rb.model, name)
                .into_iter()
                .next()
                .ok_or_else(|| {
                    err(format!(
                        "no joint called '{name}' in {} (it has {})",
                        take.name,
                        rb.model.v_names.join(", ")
                    ))
                });
        }
        let bvh = take.bvh().ok_or_else(|| err("no take loaded"))?;
        let Some(r) = current else {
            return channel_by_range(bvh, name, self.params.take.joints);
        };
        if let Some(c) = best_coordinate(r, name) {
            return Ok(c);
        }
        // a BVH name the model does not have (locked, or the results are of another model)
        let c = channel_by_range(bvh, name, self.params.take.joints)?;
        match r.model.v_index(&c) {
            Some(_) => Ok(c),
            None if self.fresh_results().is_some() => Err(err(format!(
                "{name} has no coordinate in the model (locked or outside the subtree?)"
            ))),
            None => Ok(c),
        }
    }
}
