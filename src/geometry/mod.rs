//! From a point of the normalized workspace to joint angles: the triangle
//! conditions, base direction and linear transform ([`workspace`]), the
//! 2-link inverse kinematics ([`ik`]), and both together ([`pose`]).

pub mod ik;
pub mod pose;
pub mod workspace;
