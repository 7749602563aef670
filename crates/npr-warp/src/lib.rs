//! Post-rendering 3D warping with projective textures.
