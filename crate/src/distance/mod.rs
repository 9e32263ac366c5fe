//! Distances between skeleton segments (and their volumes) and environment
//! primitives. (Being written.)
