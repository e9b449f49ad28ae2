//! kousen's bounding volume hierarchy (placeholder until the build lands).
