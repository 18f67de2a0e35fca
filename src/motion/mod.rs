//! Motion processing: channels → smooth q, v, a; blending (in progress).
