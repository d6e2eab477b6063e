//! From a point of the normalized workspace to joint angles: the triangle
//! conditions, base direction and linear transform ([`workspace`]), the
//! 2-link inverse kinematics ([`ik`]), both together ([`pose`]), and
//! end-effector paths with the joint rates along them ([`path`]) and bounds
//! of those rates over a stretch of a path ([`jet_bound`]).

pub mod ik;
pub mod jet_bound;
pub mod path;
pub mod pose;
pub mod workspace;
