//! [`AnimationError`]: a skin, morph target or animation sampler that cannot be used.

/// Why a skin, morph target or animation sampler was refused. Loading wraps it in
/// [`crate::io::LoadError::Animation`] with the file and the place in it; building a
/// [`super::Sampler`] by hand returns it as it is.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AnimationError {
    /// A sampler has no key.
    #[error("the sampler has no keys")]
    NoKeys,
    /// A key time or output value is NaN or infinite.
    #[error("non-finite {what} at key {key}")]
    NonFiniteKey {
        /// `"time"` or `"value"`.
        what: &'static str,
        /// The key (for a value, the key it belongs to).
        key: usize,
    },
    /// Key times must increase strictly (glTF 2.0, §3.11 Animations: sampler input
    /// times are strictly increasing, `time[n + 1] > time[n]`).
    #[error("key time {time} at key {key} does not increase (previous key at {previous})")]
    TimesNotIncreasing {
        /// The first key whose time is not above its predecessor's.
        key: usize,
        /// Its time.
        time: f32,
        /// The previous key's time.
        previous: f32,
    },
    /// A CUBICSPLINE sampler needs three outputs (in-tangent, value, out-tangent) per key.
    #[error("CUBICSPLINE needs 3 outputs per key: {keys} keys, {outputs} outputs of width {width}")]
    CubicSplineOutputs {
        /// Key count.
        keys: usize,
        /// Output elements found.
        outputs: usize,
        /// Components per output element.
        width: usize,
    },
    /// A STEP or LINEAR sampler needs one output per key.
    #[error("{keys} keys but {outputs} outputs of width {width}")]
    OutputCount {
        /// Key count.
        keys: usize,
        /// Output elements found.
        outputs: usize,
        /// Components per output element.
        width: usize,
    },
    /// A sampler's output has the wrong number of components for its target (3 for
    /// translation and scale, 4 for rotation, one per morph target for weights).
    #[error("output of {found} component(s), {target} needs {expected}")]
    OutputWidth {
        /// `"translation"`, `"rotation"`, `"scale"` or `"weights"`.
        target: &'static str,
        /// Components needed.
        expected: usize,
        /// Components found.
        found: usize,
    },
    /// A vertex refers to a joint its skin does not have.
    #[error("vertex {vertex} uses joint {joint}, the skin has {joints} joints")]
    JointOutOfRange {
        /// The primitive's vertex.
        vertex: usize,
        /// The joint index read from `JOINTS_n`.
        joint: u32,
        /// How many joints the skin lists.
        joints: usize,
    },
    /// A mesh with a skin has a primitive without `JOINTS_0` or `WEIGHTS_0`.
    #[error("the mesh is skinned but the primitive has no {attribute}")]
    MissingSkinAttribute {
        /// `"JOINTS_0"` or `"WEIGHTS_0"`.
        attribute: &'static str,
    },
    /// An attribute's component type is not one glTF allows for it.
    #[error("{attribute} must be {allowed}, found {found}")]
    AttributeType {
        /// The attribute (`"JOINTS_0"`, `"WEIGHTS_1"`, `"inverseBindMatrices"`, ...).
        attribute: String,
        /// What the specification allows.
        allowed: &'static str,
        /// What the accessor is.
        found: String,
    },
    /// A vertex weight is negative, NaN or infinite, or all of a vertex's weights are
    /// zero (it would collapse to the origin).
    #[error("vertex {vertex}: unusable skin weights ({reason})")]
    BadWeights {
        /// The primitive's vertex.
        vertex: usize,
        /// What is wrong.
        reason: String,
    },
    /// A morph target's accessor, or the default weights, do not match the primitive.
    #[error("morph target {target}: {reason}")]
    MorphTarget {
        /// The target.
        target: usize,
        /// What is wrong.
        reason: String,
    },
    /// The node hierarchy is not a forest (a node with two parents, or a cycle).
    #[error("the node hierarchy is not a tree: {reason}")]
    Hierarchy {
        /// What is wrong.
        reason: String,
    },
}

impl AnimationError {
    /// A stable short name: `no-keys`, `non-finite-key`, `times-not-increasing`,
    /// `cubic-spline-outputs`, `output-count`, `output-width`, `joint-out-of-range`,
    /// `missing-skin-attribute`, `attribute-type`, `bad-weights`, `morph-target`,
    /// `hierarchy`.
    pub fn kind(&self) -> &'static str {
        match self {
            Self::NoKeys => "no-keys",
            Self::NonFiniteKey { .. } => "non-finite-key",
            Self::TimesNotIncreasing { .. } => "times-not-increasing",
            Self::CubicSplineOutputs { .. } => "cubic-spline-outputs",
            Self::OutputCount { .. } => "output-count",
            Self::OutputWidth { .. } => "output-width",
            Self::JointOutOfRange { .. } => "joint-out-of-range",
            Self::MissingSkinAttribute { .. } => "missing-skin-attribute",
            Self::AttributeType { .. } => "attribute-type",
            Self::BadWeights { .. } => "bad-weights",
            Self::MorphTarget { .. } => "morph-target",
            Self::Hierarchy { .. } => "hierarchy",
        }
    }
}
