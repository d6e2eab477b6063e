//! From a point of the normalized workspace to joint angles: the triangle
//! conditions, base direction and linear transform ([`workspace`]), the
//! 2-link inverse kinematics ([`ik`]), both together ([`pose`]), and
//! end-effector paths with the joint rates along them ([`path`]).

pub mod ik;
pub mod path;
pub mod pose;
pub mod workspace;
