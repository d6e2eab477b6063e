//! The points a lift's check visits ([`crate::motion::lift::LiftCheck`]):
//! the vertices of the convex hulls of the scan of the normalized move
//! (tₛ = 1 s, τ = i/512, i = 0..=512) of the two fixed reference shapes, as
//! (Gv(4τ), G(3τ)) for the angles, (4·Gv′(4τ), 3·G′(3τ)) for the speeds and
//! (16·Gv″(4τ), 9·G″(3τ)) for the accelerations (the via term runs over the
//! first half of the move, the main term over all of it). The rates' hulls
//! are of the points and their negatives (the check wants |rate|), which is
//! symmetric: one vertex of each opposite pair is kept. Each table is in
//! the order of the scan (the earliest instant first).
//!
//! The values are the f64 shapes' (`Shape<f64>`), rounded to f32, the hull
//! taken of the rounded points; `tests/lift.rs` recomputes all three and
//! fails when a table differs (`LIFT_HULL_WRITE=1 cargo test --test lift`
//! rewrites them). In flash (`.progmem.data`) on the AVR, not in RAM.

use crate::math::fixed::flash_u32;
use crate::math::real::Real;

/// Which hull a vertex is of.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Set {
    /// (Gv, G): a joint's angle is q0 + (S_v − q0)·Gv + (S_f − S_v)·G.
    Angle,
    /// Their rates, per second of a 1 s move.
    Speed,
    /// Their second derivatives.
    Accel,
}

/// Vertices in all: a lift's check is this many units.
pub const UNITS: usize = ANGLE.len() + SPEED.len() + ACCEL.len();

/// Vertex `i` of the check's order (the angles' hull, the speeds', the
/// accelerations'), with its set; `None` past the last.
pub fn vertex<R: Real>(i: usize) -> Option<(Set, R, R)> {
    let (set, table, k): (Set, &[[u32; 2]], usize) = if i < ANGLE.len() {
        (Set::Angle, &ANGLE, i)
    } else if i < ANGLE.len() + SPEED.len() {
        (Set::Speed, &SPEED, i - ANGLE.len())
    } else {
        (Set::Accel, &ACCEL, i - ANGLE.len() - SPEED.len())
    };
    let row = table.get(k)?;
    let f = |w: &u32| R::from_f32(f32::from_bits(flash_u32(w)));
    Some((set, f(&row[0]), f(&row[1])))
}

// BEGIN GENERATED (tests/lift.rs, `LIFT_HULL_WRITE=1`)
/// The angles' hull: (Gv, G) as f32 bits.
#[cfg_attr(target_arch = "avr", link_section = ".progmem.data")]
pub static ANGLE: [[u32; 2]; 91] = [
    [0x00000000, 0x00000000],
    [0x3F129151, 0x3E021735],
    [0x3F160DD1, 0x3E053C65],
    [0x3F1985BC, 0x3E086DB4],
    [0x3F1CF7DF, 0x3E0BAB2D],
    [0x3F20630E, 0x3E0EF4D6],
    [0x3F23C622, 0x3E124AB6],
    [0x3F271FFE, 0x3E15ACD3],
    [0x3F2A6F8B, 0x3E191B30],
    [0x3F2DB3C0, 0x3E1C95D2],
    [0x3F30EB9E, 0x3E201CBB],
    [0x3F341633, 0x3E23AFEB],
    [0x3F37329D, 0x3E274F64],
    [0x3F3A4006, 0x3E2AFB24],
    [0x3F3D3DAA, 0x3E2EB329],
    [0x3F402AD2, 0x3E327770],
    [0x3F4306DC, 0x3E3647F3],
    [0x3F45D133, 0x3E3A24AE],
    [0x3F488956, 0x3E3E0D98],
    [0x3F4B2ED3, 0x3E4202AA],
    [0x3F4DC14A, 0x3E4603DA],
    [0x3F50406D, 0x3E4A111C],
    [0x3F52ABFC, 0x3E4E2A65],
    [0x3F5503CB, 0x3E524FA5],
    [0x3F5747BA, 0x3E5680CF],
    [0x3F5977BC, 0x3E5ABDD1],
    [0x3F5B93CF, 0x3E5F0698],
    [0x3F5D9C01, 0x3E635B12],
    [0x3F5F906C, 0x3E67BB2A],
    [0x3F617138, 0x3E6C26C8],
    [0x3F633E96, 0x3E709DD4],
    [0x3F64F8C5, 0x3E752036],
    [0x3F66A00B, 0x3E79ADD1],
    [0x3F6834B8, 0x3E7E468A],
    [0x3F69B724, 0x3E817521],
    [0x3F6B27AE, 0x3E83CC6C],
    [0x3F6C86BD, 0x3E862917],
    [0x3F6DD4BC, 0x3E888B0F],
    [0x3F6F121B, 0x3E8AF243],
    [0x3F703F4F, 0x3E8D5E9E],
    [0x3F715CCF, 0x3E8FD00F],
    [0x3F726B17, 0x3E924680],
    [0x3F736AA3, 0x3E94C1DB],
    [0x3F745BF2, 0x3E97420C],
    [0x3F753F83, 0x3E99C6FA],
    [0x3F7615D5, 0x3E9C508F],
    [0x3F76DF69, 0x3E9EDEB3],
    [0x3F779CBD, 0x3EA1714B],
    [0x3F784E51, 0x3EA4083E],
    [0x3F78F4A1, 0x3EA6A373],
    [0x3F79902A, 0x3EA942CD],
    [0x3F7A2164, 0x3EABE630],
    [0x3F7AA8C9, 0x3EAE8D81],
    [0x3F7B26CD, 0x3EB138A2],
    [0x3F7B9BE3, 0x3EB3E774],
    [0x3F7C087D, 0x3EB699DA],
    [0x3F7C6D08, 0x3EB94FB4],
    [0x3F7CC9EE, 0x3EBC08E2],
    [0x3F7D1F98, 0x3EBEC544],
    [0x3F7D6E6A, 0x3EC184B9],
    [0x3F7DB6C7, 0x3EC4471F],
    [0x3F7DF90C, 0x3EC70C54],
    [0x3F7E3595, 0x3EC9D436],
    [0x3F7E6CBA, 0x3ECC9EA2],
    [0x3F7E9ED1, 0x3ECF6B73],
    [0x3F7ECC2C, 0x3ED23A87],
    [0x3F7EF519, 0x3ED50BB8],
    [0x3F7F19E5, 0x3ED7DEE1],
    [0x3F7F3AD8, 0x3EDAB3DF],
    [0x3F7F5839, 0x3EDD8A8A],
    [0x3F7F724A, 0x3EE062BD],
    [0x3F7F894C, 0x3EE33C52],
    [0x3F7F9D7C, 0x3EE61723],
    [0x3F7FAF15, 0x3EE8F309],
    [0x3F7FBE50, 0x3EEBCFDD],
    [0x3F7FCB62, 0x3EEEAD78],
    [0x3F7FD67E, 0x3EF18BB2],
    [0x3F7FDFD6, 0x3EF46A66],
    [0x3F7FE797, 0x3EF7496A],
    [0x3F7FEDEE, 0x3EFA2898],
    [0x3F7FF305, 0x3EFD07C8],
    [0x3F7FF704, 0x3EFFE6D3],
    [0x3F7FFA12, 0x3F0162C8],
    [0x3F7FFC52, 0x3F02D1ED],
    [0x3F7FFDE7, 0x3F0440C5],
    [0x3F7FFEF1, 0x3F05AF3B],
    [0x3F7FFF8F, 0x3F071D3C],
    [0x3F7FFFDF, 0x3F088AB5],
    [0x3F7FFFFC, 0x3F09F792],
    [0x3F800000, 0x3F0B63C0],
    [0x3F800000, 0x3F800000],
];
/// The speeds' hull (one of each opposite pair).
#[cfg_attr(target_arch = "avr", link_section = ".progmem.data")]
pub static SPEED: [[u32; 2]; 34] = [
    [0x40DE20A1, 0x3FB2E736],
    [0x40DF38F4, 0x3FB5D8E0],
    [0x40E007DE, 0x3FB8CE2B],
    [0x40E08BC0, 0x3FBBC6E9],
    [0x40E0C353, 0x3FBEC2E9],
    [0x40E0ADAE, 0x3FC1C1FA],
    [0x40E04A4D, 0x3FC4C3E7],
    [0x40DF990E, 0x3FC7C87C],
    [0x40DE9A32, 0x3FCACF80],
    [0x40DD4E64, 0x3FCDD8BB],
    [0x40DBB6AF, 0x3FD0E3F1],
    [0x40D9D485, 0x3FD3F0E7],
    [0x40D7A9B4, 0x3FD6FF5E],
    [0x40D53867, 0x3FDA0F15],
    [0x40D28321, 0x3FDD1FCA],
    [0x40CF8CB4, 0x3FE0313A],
    [0x40CC583C, 0x3FE3431F],
    [0x40C8E919, 0x3FE65532],
    [0x40C542E7, 0x3FE96729],
    [0x40C16973, 0x3FEC78BB],
    [0x40BD60B7, 0x3FEF899B],
    [0x40B92CCD, 0x3FF2997B],
    [0x40B4D1E8, 0x3FF5A80B],
    [0x3DE1D9E4, 0x40374F75],
    [0x3DC0EB23, 0x40377C51],
    [0x3DA31CB3, 0x40379F5D],
    [0x3D884916, 0x4037B893],
    [0x3D609810, 0x4037C7ED],
    [0x3D36050B, 0x4037CD69],
    [0x3D109591, 0x4037C905],
    [0x3CE0110C, 0x4037BAC3],
    [0x3CA83E7B, 0x4037A2A6],
    [0x3C7275B1, 0x403780B2],
    [0x3C25247F, 0x403754EE],
];
/// The accelerations' hull (one of each opposite pair).
#[cfg_attr(target_arch = "avr", link_section = ".progmem.data")]
pub static ACCEL: [[u32; 2]; 42] = [
    [0x42898884, 0x4120EB8D],
    [0x4289266A, 0x41226EFD],
    [0x4288671C, 0x4123EEA8],
    [0x428745B1, 0x41256A46],
    [0x4285BD8B, 0x4126E18E],
    [0x4283CA67, 0x41285433],
    [0x4281686C, 0x4129C1E6],
    [0x427D2884, 0x412B2A57],
    [0x42769643, 0x412C8D33],
    [0x426F15CA, 0x412DEA23],
    [0x4266A437, 0x412F40D0],
    [0x425D4031, 0x413090DF],
    [0x4252EA04, 0x4131D9F5],
    [0x4247A3BF, 0x41331BB4],
    [0x423B7147, 0x413455BA],
    [0x422E586C, 0x413587A6],
    [0x422060F1, 0x4136B114],
    [0x42119496, 0x4137D19E],
    [0x4201FF16, 0x4138E8DD],
    [0x41E35C3A, 0x4139F668],
    [0xC201B4AB, 0x4143702E],
    [0xC2139CA6, 0x4143C864],
    [0xC224EECF, 0x41441051],
    [0xC235962F, 0x41444785],
    [0xC2457F59, 0x41446D8E],
    [0xC254989F, 0x414481FD],
    [0xC262D231, 0x41448464],
    [0xC2701E43, 0x41447457],
    [0xC27C7120, 0x4144516A],
    [0xC283E09C, 0x41441B34],
    [0xC2890396, 0x4143D14D],
    [0xC28D9EE2, 0x41437351],
    [0xC291B0FA, 0x414300DD],
    [0xC295395F, 0x41427991],
    [0xC2983893, 0x4141DD10],
    [0xC29AB00A, 0x41412B01],
    [0xC29CA21A, 0x4140630D],
    [0xC29E11E9, 0x413F84E0],
    [0xC29F0357, 0x413E902C],
    [0xC29F7AF1, 0x413D84A6],
    [0xC29F7DD1, 0x413C6207],
    [0x00000000, 0xC140D599],
];
// END GENERATED
