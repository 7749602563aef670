//! CPU mesh, topology, curvature tensor and the N = H solve.

pub mod mesh;

pub use mesh::Mesh;
