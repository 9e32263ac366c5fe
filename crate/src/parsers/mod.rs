//! Readers: text and bytes turned into the library's types, in one place
//! (as Pinocchio's `parsers/`). Each reader refuses bad input with an error
//! naming the element or field, and states its caps in its module docs.
//!
//! | module | reads | into |
//! |---|---|---|
//! | [`urdf`] | URDF (XML, with `urdf-rs`) | a [`RobotSpec`](crate::kinematics::RobotSpec) in standard DH, the chain's links and meshes, a report |
//! | [`srdf`] | SRDF (`disable_collisions`, with `quick-xml`) | pairs of rows left out of the self-collision query |
//! | [`mesh`] | STL, OBJ, COLLADA (`mesh-loader`), glTF / GLB (`gltf`); mesh names of a URDF among files given by path | a [`TriMesh`](crate::mesh::TriMesh) |
//! | [`track`] | keypoint tracks (JSON, CSV) and BVH motion capture | timestamps and keypoint positions per frame |
//!
//! What is done with what was read stays in its domain: the DH table from
//! the joint axes in [`crate::kinematics::dh_from_axes`], volumes fitted to
//! meshes in [`crate::fitting`], a track's repairs and its fit onto the
//! human in [`crate::human::track`].

pub mod mesh;
pub mod srdf;
pub mod track;
pub mod urdf;
