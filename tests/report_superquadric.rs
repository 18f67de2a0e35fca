//! Superquadric geometry (Barr 1981): every sampled point lies on the implicit surface
//! `(|x/a|^(2/ε2) + |y/b|^(2/ε2))^(ε2/ε1) + |z/c|^(2/ε1) = 1`, placed by the shape's centre and
//! rotation; small exponents approach the bounding box; the wireframe's edges join neighbours.

use articula::model::Superquadric;
use articula::report::superquadric::{SuperquadricMesh, inside_outside, superquadric_points};
use articula::spatial::SpatialTransform;
use nalgebra::{Matrix3, Rotation3, Vector3};

fn shape(size: [f64; 3], exponents: [f64; 2]) -> Superquadric {
    Superquadric {
        center: Vector3::zeros(),
        rot: Matrix3::identity(),
        size: Vector3::new(size[0], size[1], size[2]),
        exponents,
    }
}

#[test]
fn ellipsoid_points_satisfy_the_quadric() {
    let sq = shape([0.3, 0.2, 0.5], [1.0, 1.0]);
    let pts = superquadric_points(&sq, 17, 24);
    assert_eq!(pts.len(), 17 * 24);
    for p in &pts {
        let f = (p.x / 0.3).powi(2) + (p.y / 0.2).powi(2) + (p.z / 0.5).powi(2);
        assert!((f - 1.0).abs() < 1e-12, "{p:?}: {f}");
    }
    // the poles and the equator's extremes are reached
    assert!((pts[0].z + 0.5).abs() < 1e-12);
    assert!((pts.last().unwrap().z - 0.5).abs() < 1e-12);
    let max_x = pts.iter().map(|p| p.x).fold(f64::MIN, f64::max);
    assert!((max_x - 0.3).abs() < 1e-12);
}

#[test]
fn placed_shapes_satisfy_the_general_implicit_equation() {
    let rot = *Rotation3::from_euler_angles(0.3, -0.7, 1.1).matrix();
    for exponents in [[0.5, 1.5], [1.0, 0.3], [2.0, 2.0], [0.2, 0.2]] {
        let sq = Superquadric {
            center: Vector3::new(0.1, -0.2, 0.4),
            rot,
            size: Vector3::new(0.05, 0.08, 0.2),
            exponents,
        };
        for p in superquadric_points(&sq, 9, 12) {
            let f = inside_outside(&sq, &p);
            assert!((f - 1.0).abs() < 1e-9, "{exponents:?}: {f}");
        }
        assert!(inside_outside(&sq, &sq.center) < 1.0);
        assert!(inside_outside(&sq, &(sq.center + rot * Vector3::new(0.0, 0.0, 0.25))) > 1.0);
    }
}

#[test]
fn box_like_exponents_approach_the_box() {
    let (a, b, c) = (0.1, 0.2, 0.3);
    // at a small exponent, the "corner" sample (η = ω = π/4 family) sits near the box corner
    let sq = shape([a, b, c], [0.02, 0.02]);
    let pts = superquadric_points(&sq, 5, 8);
    for p in &pts {
        assert!(p.x.abs() <= a + 1e-12 && p.y.abs() <= b + 1e-12 && p.z.abs() <= c + 1e-12);
    }
    let corner = pts
        .iter()
        .map(|p| (p.x.abs() / a).min(p.y.abs() / b).min(p.z.abs() / c))
        .fold(0.0, f64::max);
    assert!(corner > 0.97, "nearest approach to a corner: {corner}");
    // and the ellipsoid's corner point is far from it: cos(π/4)² = 0.5
    let ell = superquadric_points(&shape([a, b, c], [1.0, 1.0]), 5, 8);
    let ell_corner = ell
        .iter()
        .map(|p| (p.x.abs() / a).min(p.y.abs() / b).min(p.z.abs() / c))
        .fold(0.0, f64::max);
    assert!(ell_corner < 0.71, "{ell_corner}");
}

#[test]
fn mesh_edges_join_neighbours_and_skip_pole_rings() {
    let (n_u, n_v) = (6, 10);
    let sq = shape([0.1, 0.1, 0.4], [1.0, 1.0]);
    let mesh = SuperquadricMesh::new(&sq, n_u, n_v);
    assert_eq!(mesh.points.len(), n_u * n_v);
    // (n_u − 1)·n_v meridian segments + (n_u − 2)·n_v parallel segments
    assert_eq!(mesh.edges.len(), (n_u - 1) * n_v + (n_u - 2) * n_v);
    for &[i, j] in &mesh.edges {
        let len = (mesh.points[i] - mesh.points[j]).norm();
        assert!(len > 1e-9 && len < 0.4, "edge {i}-{j}: {len}");
    }
    // placing the mesh moves every segment by the transform
    let x = SpatialTransform::from_translation(Vector3::new(1.0, 2.0, 3.0));
    for ((p, q), &[i, j]) in mesh.edges_in(&x).zip(&mesh.edges) {
        assert_eq!(p, mesh.points[i] + Vector3::new(1.0, 2.0, 3.0));
        assert_eq!(q, mesh.points[j] + Vector3::new(1.0, 2.0, 3.0));
    }
}

#[test]
fn tiny_resolutions_are_raised_not_panicking() {
    let sq = shape([0.1, 0.1, 0.1], [1.0, 1.0]);
    assert_eq!(superquadric_points(&sq, 0, 0).len(), 2 * 3);
    let mesh = SuperquadricMesh::new(&sq, 1, 1);
    assert_eq!(mesh.edges.len(), 3);
}
