//! Control points as DH values and their Jacobians. (Being written.)
