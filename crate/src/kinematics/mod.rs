//! DH robots and forward kinematics. (Being written.)
