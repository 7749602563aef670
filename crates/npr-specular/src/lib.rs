//! Stylized specular highlights by curvature-driven texture projectors.
