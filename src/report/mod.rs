//! Reports: SVG charts and CSV tables (in progress).
