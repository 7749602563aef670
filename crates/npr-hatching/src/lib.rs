//! Real-time image-space hatching with tonal art maps.
