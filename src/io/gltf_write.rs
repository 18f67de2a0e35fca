//! glTF 2.0 binary (`.glb`) writer: a skeleton as nodes, mesh parts skinned rigidly to its
//! joints, and one animation of the joints' translations and rotations.
//!
//! Input is a plain [`Rig`] already in glTF's conventions: metres, +Y up, right-handed,
//! quaternions `[x, y, z, w]`, times in seconds (the caller converts from a take's axes and
//! unit, see `pipeline::animation`). The JSON chunk is built with the `gltf-json` crate's typed
//! structs; the binary container around it (a 12-byte header and two chunks, glTF 2.0 spec
//! §4.4) is written here, since it is three little-endian words per chunk and a crate for it
//! would add nothing. Numbers are stored as `f32`, glTF's only float type (about 1e-7
//! relative: 0.2 µm over 2 m).
//!
//! Layout: one node per joint (file order, `children` per `parent`), a mesh node with the skin,
//! the scene holding the root joint and the mesh node. The bind pose is the joints' `rest`
//! translations with no rotation, so each inverse bind matrix is a translation by minus the
//! joint's rest position; each vertex has one joint with weight 1 (`JOINTS_0` / `WEIGHTS_0`).

use crate::error::Error;
use gltf_json as json;
use json::validation::Checked::Valid;
use json::validation::USize64;
use nalgebra::Vector3;

/// One joint of the skeleton.
#[derive(Debug, Clone, PartialEq)]
pub struct RigJoint {
    /// Node name.
    pub name: String,
    /// Parent joint (index into `Rig::joints`, `parent < self`); `None` for the root.
    pub parent: Option<usize>,
    /// Translation in the parent's frame in the bind pose (m).
    pub rest: [f64; 3],
}

/// A triangle mesh moving rigidly with one joint.
#[derive(Debug, Clone, PartialEq)]
pub struct RigPart {
    /// The joint it moves with.
    pub joint: usize,
    /// Vertices in the joint's frame (m).
    pub vertices: Vec<[f64; 3]>,
    /// Triangles as vertex indices, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

/// A skinned, animated skeleton in glTF's conventions (m, +Y up, s).
#[derive(Debug, Clone, PartialEq)]
pub struct Rig {
    /// The asset's name (the take's file stem).
    pub name: String,
    /// Joints, parents first.
    pub joints: Vec<RigJoint>,
    /// Link meshes.
    pub parts: Vec<RigPart>,
    /// Key times (s), increasing.
    pub times: Vec<f64>,
    /// Per joint, its translation in the parent's frame at each time (m), if animated.
    pub translations: Vec<Option<Vec<[f64; 3]>>>,
    /// Per joint, its rotation in the parent's frame at each time (`[x, y, z, w]`), if animated.
    pub rotations: Vec<Option<Vec<[f64; 4]>>>,
}

/// The `.glb` bytes of `rig`.
pub fn to_glb(rig: &Rig) -> Result<Vec<u8>, Error> {
    check(rig)?;
    let mut b = Builder::default();
    // skeleton: one node per joint
    let rest_world = rest_positions(rig);
    let nodes: Vec<json::Index<json::scene::Node>> = rig
        .joints
        .iter()
        .map(|j| {
            b.root.push(json::scene::Node {
                name: Some(j.name.clone()),
                translation: Some(j.rest.map(|x| x as f32)),
                ..Default::default()
            })
        })
        .collect();
    for (i, j) in rig.joints.iter().enumerate() {
        if let Some(p) = j.parent {
            b.root.nodes[p]
                .children
                .get_or_insert_with(Vec::new)
                .push(nodes[i]);
        }
    }
    // skin: inverse bind matrices are translations by minus the rest positions
    let ibm: Vec<f32> = rest_world
        .iter()
        .flat_map(|p| {
            let mut m = [0.0f32; 16];
            for d in 0..3 {
                m[5 * d] = 1.0;
                m[12 + d] = -p[d] as f32;
            }
            m[15] = 1.0;
            m
        })
        .collect();
    let ibm = b.floats(&ibm, json::accessor::Type::Mat4, false);
    let skin = b.root.push(json::skin::Skin {
        extensions: None,
        extras: Default::default(),
        inverse_bind_matrices: Some(ibm),
        joints: nodes.clone(),
        name: Some("skeleton".into()),
        skeleton: nodes.first().copied(),
    });
    let mut scene_nodes = nodes.first().copied().into_iter().collect::<Vec<_>>();
    if let Some(mesh) = mesh(&mut b, rig, &rest_world) {
        scene_nodes.push(b.root.push(json::scene::Node {
            name: Some("links".into()),
            mesh: Some(mesh),
            skin: Some(skin),
            ..Default::default()
        }));
    }
    animation(&mut b, rig, &nodes);
    let scene = b.root.push(json::scene::Scene {
        extensions: None,
        extras: Default::default(),
        name: Some(rig.name.clone()),
        nodes: scene_nodes,
    });
    b.root.scene = Some(scene);
    b.root.asset.generator = Some(format!("articula {}", env!("CARGO_PKG_VERSION")));
    b.finish()
}

/// Refuses a rig whose arrays disagree (a bug in the caller, said plainly).
fn check(rig: &Rig) -> Result<(), Error> {
    let n = rig.joints.len();
    let bad = |what: String| Err(Error::Invalid(format!("glTF export: {what}")));
    if n == 0
        || rig
            .joints
            .iter()
            .enumerate()
            .any(|(i, j)| j.parent.is_some_and(|p| p >= i))
    {
        return bad("a skeleton needs joints, each after its parent".into());
    }
    if rig.joints.iter().skip(1).any(|j| j.parent.is_none()) || rig.joints[0].parent.is_some() {
        return bad("a skeleton has one root, the first joint".into());
    }
    if rig.translations.len() != n || rig.rotations.len() != n {
        return bad("one translation and one rotation track slot per joint".into());
    }
    let k = rig.times.len();
    let tracks_ok = rig.translations.iter().flatten().all(|t| t.len() == k)
        && rig.rotations.iter().flatten().all(|r| r.len() == k);
    if !tracks_ok || rig.times.windows(2).any(|w| w[1] <= w[0]) {
        return bad("every track has one key per time, times increasing".into());
    }
    let parts_ok = rig.parts.iter().all(|p| {
        p.joint < n
            && p.triangles
                .iter()
                .flatten()
                .all(|&v| (v as usize) < p.vertices.len())
    });
    if !parts_ok {
        return bad("a mesh part names a joint or vertex that does not exist".into());
    }
    Ok(())
}

/// World position of every joint in the bind pose (m).
fn rest_positions(rig: &Rig) -> Vec<Vector3<f64>> {
    let mut out: Vec<Vector3<f64>> = Vec::with_capacity(rig.joints.len());
    for j in &rig.joints {
        let base = j.parent.map_or(Vector3::zeros(), |p| out[p]);
        out.push(base + Vector3::from(j.rest));
    }
    out
}

/// One primitive holding every part, each vertex bound to its part's joint.
fn mesh(
    b: &mut Builder,
    rig: &Rig,
    rest_world: &[Vector3<f64>],
) -> Option<json::Index<json::mesh::Mesh>> {
    let (mut positions, mut normals, mut joints, mut weights, mut indices) =
        (vec![], vec![], vec![], vec![], vec![]);
    for part in &rig.parts {
        let base = (positions.len() / 3) as u32;
        let world: Vec<Vector3<f64>> = part
            .vertices
            .iter()
            .map(|v| rest_world[part.joint] + Vector3::from(*v))
            .collect();
        for n in vertex_normals(&world, &part.triangles) {
            normals.extend(n.iter().map(|&x| x as f32));
        }
        positions.extend(world.iter().flat_map(|p| p.iter().map(|&x| x as f32)));
        joints.extend(world.iter().flat_map(|_| [part.joint as u16, 0, 0, 0]));
        weights.extend(world.iter().flat_map(|_| [1.0f32, 0.0, 0.0, 0.0]));
        indices.extend(part.triangles.iter().flatten().map(|&v| base + v));
    }
    if indices.is_empty() {
        return None;
    }
    use json::mesh::Semantic;
    let attributes = [
        (
            Semantic::Positions,
            b.floats(&positions, json::accessor::Type::Vec3, true),
        ),
        (
            Semantic::Normals,
            b.floats(&normals, json::accessor::Type::Vec3, false),
        ),
        (Semantic::Joints(0), b.joints(&joints)),
        (
            Semantic::Weights(0),
            b.floats(&weights, json::accessor::Type::Vec4, false),
        ),
    ]
    .into_iter()
    .map(|(s, a)| (Valid(s), a))
    .collect();
    let indices = b.indices(&indices);
    Some(b.root.push(json::mesh::Mesh {
        extensions: None,
        extras: Default::default(),
        name: Some("links".into()),
        primitives: vec![json::mesh::Primitive {
            attributes,
            extensions: None,
            extras: Default::default(),
            indices: Some(indices),
            material: None,
            mode: Valid(json::mesh::Mode::Triangles),
            targets: None,
        }],
        weights: None,
    }))
}

/// Area-weighted vertex normals (a vertex in no triangle gets +Y).
fn vertex_normals(p: &[Vector3<f64>], triangles: &[[u32; 3]]) -> Vec<[f64; 3]> {
    let mut n = vec![Vector3::zeros(); p.len()];
    for t in triangles {
        let [a, b, c] = t.map(|v| v as usize);
        let face = (p[b] - p[a]).cross(&(p[c] - p[a]));
        for v in [a, b, c] {
            n[v] += face;
        }
    }
    n.iter()
        .map(|v| {
            let v = v.try_normalize(1e-30).unwrap_or_else(Vector3::y);
            [v.x, v.y, v.z]
        })
        .collect()
}

/// One animation: a sampler and a channel per animated translation and rotation.
fn animation(b: &mut Builder, rig: &Rig, nodes: &[json::Index<json::scene::Node>]) {
    if rig.times.is_empty() {
        return;
    }
    let times: Vec<f32> = rig.times.iter().map(|&t| t as f32).collect();
    let input = b.floats(&times, json::accessor::Type::Scalar, true);
    let mut samplers = vec![];
    let mut channels = vec![];
    let mut add = |b: &mut Builder, node, path, values: Vec<f32>, ty| {
        let output = b.floats(&values, ty, false);
        channels.push(json::animation::Channel {
            sampler: json::Index::new(samplers.len() as u32),
            target: json::animation::Target {
                extensions: None,
                extras: Default::default(),
                node,
                path: Valid(path),
            },
            extensions: None,
            extras: Default::default(),
        });
        samplers.push(json::animation::Sampler {
            extensions: None,
            extras: Default::default(),
            input,
            interpolation: Valid(json::animation::Interpolation::Linear),
            output,
        });
    };
    use json::animation::Property;
    for (i, &node) in nodes.iter().enumerate() {
        if let Some(t) = &rig.translations[i] {
            let v = t.iter().flatten().map(|&x| x as f32).collect();
            add(
                b,
                node,
                Property::Translation,
                v,
                json::accessor::Type::Vec3,
            );
        }
        if let Some(r) = &rig.rotations[i] {
            let v = r.iter().flatten().map(|&x| x as f32).collect();
            add(b, node, Property::Rotation, v, json::accessor::Type::Vec4);
        }
    }
    b.root.push(json::Animation {
        extensions: None,
        extras: Default::default(),
        channels,
        name: Some(rig.name.clone()),
        samplers,
    });
}

/// The JSON root and the binary chunk being filled, one buffer view per accessor.
#[derive(Default)]
struct Builder {
    root: json::Root,
    bin: Vec<u8>,
}

impl Builder {
    /// A buffer view over `bytes`, aligned to 4 bytes in the binary chunk.
    fn view(&mut self, bytes: &[u8]) -> json::Index<json::buffer::View> {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: None,
            extensions: None,
            extras: Default::default(),
        })
    }

    fn accessor(
        &mut self,
        bytes: &[u8],
        count: usize,
        component: json::accessor::ComponentType,
        ty: json::accessor::Type,
        bounds: Option<(Vec<f32>, Vec<f32>)>,
    ) -> json::Index<json::Accessor> {
        let view = self.view(bytes);
        let (min, max) = bounds.map_or((None, None), |(lo, hi)| {
            (Some(json::Value::from(lo)), Some(json::Value::from(hi)))
        });
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Valid(json::accessor::GenericComponentType(component)),
            extensions: None,
            extras: Default::default(),
            type_: Valid(ty),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    /// `f32` data of type `ty`, with per-component min and max when `bounds` (glTF requires
    /// them on positions and animation inputs).
    fn floats(
        &mut self,
        v: &[f32],
        ty: json::accessor::Type,
        bounds: bool,
    ) -> json::Index<json::Accessor> {
        let width = ty.multiplicity();
        let bounds = bounds.then(|| {
            let mut lo = vec![f32::INFINITY; width];
            let mut hi = vec![f32::NEG_INFINITY; width];
            for c in v.chunks(width) {
                for d in 0..width {
                    lo[d] = lo[d].min(c[d]);
                    hi[d] = hi[d].max(c[d]);
                }
            }
            (lo, hi)
        });
        let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
        let count = v.len() / width;
        self.accessor(
            &bytes,
            count,
            json::accessor::ComponentType::F32,
            ty,
            bounds,
        )
    }

    fn joints(&mut self, v: &[u16]) -> json::Index<json::Accessor> {
        let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
        let ty = json::accessor::Type::Vec4;
        self.accessor(
            &bytes,
            v.len() / 4,
            json::accessor::ComponentType::U16,
            ty,
            None,
        )
    }

    fn indices(&mut self, v: &[u32]) -> json::Index<json::Accessor> {
        let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
        let ty = json::accessor::Type::Scalar;
        self.accessor(
            &bytes,
            v.len(),
            json::accessor::ComponentType::U32,
            ty,
            None,
        )
    }

    /// The `.glb`: header, JSON chunk padded with spaces, BIN chunk padded with zeros.
    fn finish(mut self) -> Result<Vec<u8>, Error> {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        if !self.bin.is_empty() {
            self.root.push(json::Buffer {
                byte_length: USize64::from(self.bin.len()),
                name: None,
                uri: None,
                extensions: None,
                extras: Default::default(),
            });
        }
        let mut text = self
            .root
            .to_vec()
            .map_err(|e| Error::Invalid(format!("glTF export: JSON: {e}")))?;
        while !text.len().is_multiple_of(4) {
            text.push(b' ');
        }
        let bin_chunk = if self.bin.is_empty() {
            0
        } else {
            8 + self.bin.len()
        };
        let total = 12 + 8 + text.len() + bin_chunk;
        let too_big = || Error::Invalid("glTF export: the file would pass 4 GiB".into());
        let word = |n: usize| {
            u32::try_from(n)
                .map(u32::to_le_bytes)
                .map_err(|_| too_big())
        };
        let mut out = Vec::with_capacity(total);
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&word(total)?);
        out.extend_from_slice(&word(text.len())?);
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&text);
        if !self.bin.is_empty() {
            out.extend_from_slice(&word(self.bin.len())?);
            out.extend_from_slice(b"BIN\0");
            out.extend_from_slice(&self.bin);
        }
        Ok(out)
    }
}
