//! The session command language (in progress).
