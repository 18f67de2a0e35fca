//! Joint-space motion: BVH channels → q (take), continuity (unwrap), smoothing, derivatives,
//! C² ramps and blending/warping of takes, a helper root folded (fold) and bone translations
//! welded (weld), twist helpers inside a long bone folded into the next joint (twist).

pub mod blend;
pub mod contact;
pub mod derive;
pub mod euler;
pub mod fold;
pub mod ramp;
pub mod smooth;
pub mod spline;
pub mod take;
pub mod trim;
pub mod twist;
pub mod unwrap;
pub mod weld;
