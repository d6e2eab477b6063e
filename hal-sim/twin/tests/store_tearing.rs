//! Tear-proof saves (`config::store`, module doc "Tear-proof by construction"):
//! a power loss at every byte a save writes, leaving every kind of value in the
//! torn byte, from every kind of prior EEPROM content (blank, a normal pair,
//! unequal or equal-sequence copies, corrupt, uncommitted or foreign copies,
//! wrapped counters). After each, the configuration that loads is the one that
//! loaded before the save or the one being saved, never a mixture, and once
//! the first copy is complete it is the new one.

use embedded_storage::{ReadStorage, Storage};
use hal_sim::devices::SimEeprom;
use hal_sim::rng::Rng;
use touch_arm::config::settings::{Config, SpeedPreset};
use touch_arm::config::store::*;
use touch_arm::motion::plan::LawKind;
use touch_arm::seam::StorageError;
use touch_arm::touch::map::Calibration;

/// The power-loss sweep of a small record kept as two tear-proof copies
/// whose `load` returns `(Source, seq, value)` (the access settings, the
/// display overrides): from every kind of prior pair of copies, a save cut
/// at every byte it writes, with every kind of value in the torn byte,
/// loads the value before the save or the new one (the new one once the
/// first copy is complete), and a save after it works. `$corrupt` is a body
/// byte and the bit flipped to make a copy corrupt; `$outside` names the
/// slots in the message when a byte outside them is written. Counts the
/// cases.
macro_rules! torn_two_copy_saves {
    ($m:ident, $len:expr, $slot_a:expr, $slot_b:expr, $sets:expr, $corrupt:expr, $outside:expr) => {{
        let (len, slot_a, slot_b, sets) = ($len, $slot_a, $slot_b, $sets);
        #[derive(Clone, Copy, Debug)]
        enum P {
            Blank,
            Valid(usize, u16),
            Corrupt(usize, u16),
            Uncommitted(usize, u16),
        }
        let fill = |e: &mut SimEeprom, at: u16, p: P| {
            let bytes = match p {
                P::Blank => vec![0xFF; len],
                P::Valid(k, seq) => $m::encode(&sets[k], seq).to_vec(),
                P::Corrupt(k, seq) => {
                    let mut r = $m::encode(&sets[k], seq);
                    r[$corrupt.0] ^= $corrupt.1;
                    r.to_vec()
                }
                P::Uncommitted(k, seq) => {
                    let mut r = $m::encode(&sets[k], seq);
                    r[0] = UNCOMMITTED;
                    r.to_vec()
                }
            };
            e.mem[at as usize..at as usize + len].copy_from_slice(&bytes);
        };
        use P::*;
        let priors = [
            (Blank, Blank),
            (Valid(1, 4), Valid(1, 4)),
            (Valid(2, 4), Valid(1, 4)),
            (Valid(1, 9), Valid(2, 8)),
            (Valid(1, 0xFFFF), Valid(2, 0)),
            (Valid(2, 5), Corrupt(1, 6)),
            (Corrupt(1, 6), Valid(2, 5)),
            (Valid(1, 5), Uncommitted(3, 6)),
            (Uncommitted(3, 6), Valid(1, 5)),
        ];
        let mut cases = 0u64;
        for (pa, pb) in priors {
            let mut prior = SimEeprom::new();
            fill(&mut prior, slot_a, pa);
            fill(&mut prior, slot_b, pb);
            let before = $m::load(&mut prior.clone());
            for new in &sets {
                let mut dry = prior.clone();
                let mut rec = Recorder { inner: &mut dry, writes: Vec::new() };
                let seq = $m::save(&mut rec, new).expect("a save without power loss succeeds");
                let writes = rec.writes;
                let inside =
                    |a: u16| (slot_a..slot_a + len as u16).contains(&a) || (slot_b..slot_b + len as u16).contains(&a);
                assert!(writes.iter().all(|(a, _)| inside(*a)), "a byte outside the {} written", $outside);
                let slot_of = |a: u16| if a >= slot_b { slot_b } else { slot_a };
                let first_len = writes.iter().take_while(|(a, _)| slot_of(*a) == slot_of(writes[0].0)).count();
                for cut in 0..=writes.len() {
                    let (addr, new_byte) = writes.get(cut).copied().unwrap_or((0, 0));
                    let old_byte = prior.mem[addr as usize];
                    for torn in [0x00, 0xFF, MAGIC[0], old_byte, new_byte, 0xA5] {
                        let mut e = prior.clone();
                        e.power_loss_after(cut);
                        e.torn_value = torn;
                        let _ = $m::save(&mut e, new);
                        e.restore_power();
                        let l = $m::load(&mut e);
                        let ctx = format!("prior ({pa:?}, {pb:?}), cut {cut} of {}, torn {torn:#04x}", writes.len());
                        let is_new = (l.2, l.1) == (*new, seq) && l.0 != Source::Defaults;
                        assert!(is_new || l == before, "{ctx}: loaded {l:?}");
                        if cut >= first_len {
                            assert_eq!((l.2, l.1), (*new, seq), "{ctx}: the first copy was complete");
                        }
                        let again = $m::save(&mut e, &sets[3]).unwrap_or_else(|err| panic!("{ctx}: {err:?}"));
                        assert_eq!($m::load(&mut e).1, again, "{ctx}");
                        assert_eq!($m::load(&mut e).2, sets[3], "{ctx}");
                        cases += 1;
                    }
                }
            }
        }
        cases
    }};
}

/// The carer's access settings (`config::access`) are stored the same way:
/// a power loss at any byte of their save, with every kind of value in the
/// torn byte, from blank, equal, unequal, corrupt and uncommitted copies,
/// loads the settings before the save or the new ones, and the new ones once
/// the first copy is complete; a torn save never leaves a PIN that is
/// neither the old nor the new one. No byte outside their two slots is
/// written.
#[test]
fn a_power_loss_at_any_byte_of_an_access_save_loads_the_old_or_the_new_settings() {
    use touch_arm::config::access::{self, item, Access, Pin, ACCESS_DEFAULT, ACCESS_RECORD_LEN as LEN};
    use touch_arm::config::access::{ACCESS_SLOT_A as SLOT_A, ACCESS_SLOT_B as SLOT_B};
    let pin = Pin::parse(b"2468").unwrap();
    let locked = Access { pin, ..ACCESS_DEFAULT };
    // One digit apart: a record differing in one byte (and its CRC).
    let other_pin = Access { pin: Pin::parse(b"2469").unwrap(), ..locked };
    let custom = Access {
        hide: item::LINE | item::TOUCH,
        cap: SpeedPreset::Slow,
        pin: Pin::parse(b"13579864").unwrap(),
        switch: touch_arm::config::access::SwitchUse::On,
        sweep_ds: 45,
    };
    let sets = [ACCESS_DEFAULT, locked, other_pin, custom];
    let cases = torn_two_copy_saves!(access, LEN, SLOT_A, SLOT_B, sets, (9, 0x01), "access slots");
    eprintln!("{cases} torn access saves");
    // 9 priors × 4 records × (20 or 21 bytes a slot, twice, + the uncut
    // save) × 6 torn values.
    assert!(cases > 8_000);
}

/// The access record's layout: the documented offsets, and what load
/// refuses (each refusal leaves the defaults: no PIN, so never locked).
#[test]
fn the_access_record_round_trips_and_refuses_what_it_should() {
    use touch_arm::config::access::{self, item, Access, Pin, ACCESS_DEFAULT, ACCESS_RECORD_LEN as LEN};
    let a = Access {
        hide: item::CAL | item::FAST,
        cap: SpeedPreset::Normal,
        pin: Pin::parse(b"07734").unwrap(),
        switch: touch_arm::config::access::SwitchUse::Off,
        sweep_ds: 200,
    };
    let r = access::encode(&a, 0x1234);
    assert_eq!(&r[..18], &[b'T', b'C', 2, 0x34, 0x12, 0b1001, 1, 5, b'0', b'7', b'7', b'3', b'4', 0, 0, 0, 0, 200]);
    assert_eq!(access::decode(&r), Ok((0x1234, a)));
    assert_eq!(access::decode(&access::encode(&ACCESS_DEFAULT, 7)), Ok((7, ACCESS_DEFAULT)));
    // PINs: 4 to 8 digits, nothing else.
    for ok in [&b"0000"[..], b"12345678"] {
        assert!(Pin::parse(ok).is_some());
    }
    for bad in [&b"123"[..], b"123456789", b"12a4", b"", b"-1234"] {
        assert_eq!(Pin::parse(bad), None, "{bad:?}");
    }
    let mut bad = r;
    bad[2] = 3;
    assert_eq!(access::decode(&bad), Err(RecordError::Version(3)));
    let mut bad = r;
    bad[LEN - 1] ^= 1;
    assert_eq!(access::decode(&bad), Err(RecordError::Crc));
    // A valid CRC over an unknown item, an unknown cap, a PIN length of 1,
    // 3 or 9, a non-digit in the PIN, a byte after it, a length that does
    // not match its digits, an unknown switch flag, a sweep under 2 s or
    // over 20 s.
    for (at, v) in [
        (5, 0b10_0000),
        (6, 3),
        (7, 1),
        (7, 3),
        (7, 9),
        (9, b'x'),
        (13, b'1'),
        (7, 4),
        (7, 0),
        (16, 2),
        (17, 19),
        (17, 201),
    ] {
        let mut odd = r;
        odd[at] = v;
        let crc = touch_arm::config::crc::crc16(&odd[..LEN - 2]).to_le_bytes();
        odd[LEN - 2..].copy_from_slice(&crc);
        assert_eq!(access::decode(&odd), Err(RecordError::Invalid), "byte {at} = {v}");
    }
    // Never written, or damaged: the defaults (no PIN: unlocked).
    let mut e = SimEeprom::new();
    assert_eq!(access::load(&mut e), (Source::Defaults, 0, ACCESS_DEFAULT));
    let at = access::ACCESS_SLOT_A as usize;
    e.mem[at..at + LEN].copy_from_slice(&bad);
    assert_eq!(access::load(&mut e), (Source::Defaults, 0, ACCESS_DEFAULT));
}

/// Records every byte written through it (address, value), in order.
struct Recorder<'a> {
    inner: &'a mut SimEeprom,
    writes: Vec<(u16, u8)>,
}

impl ReadStorage for Recorder<'_> {
    type Error = StorageError;

    fn read(&mut self, offset: u32, buf: &mut [u8]) -> Result<(), StorageError> {
        self.inner.read(offset, buf)
    }

    fn capacity(&self) -> usize {
        self.inner.capacity()
    }
}

impl Storage for Recorder<'_> {
    fn write(&mut self, offset: u32, data: &[u8]) -> Result<(), StorageError> {
        for (i, &b) in data.iter().enumerate() {
            self.writes.push(((offset as usize + i) as u16, b));
        }
        self.inner.write(offset, data)
    }
}

/// Configurations that differ a lot, and ones that differ in one field only
/// (a record that changes in a few bytes is where a torn mixture would pass
/// as either).
fn configs() -> Vec<Config> {
    let mut sample = Config::DEFAULT;
    sample.joints[0].offset_us = 612.5;
    sample.joints[1].us_per_rad = -600.25;
    sample.joints[1].offset_us = 2500.0;
    sample.joints[2].min_us = 700;
    sample.touch =
        Calibration { x_min: 100, x_max: 950, y_min: 90, y_max: 900, swap_xy: true, invert_x: false, invert_y: true };
    sample.speed = SpeedPreset::Fast;
    sample.law = LawKind::Quintic;
    let mut speed = Config::DEFAULT;
    speed.joints[2].max_speed_rad_s = 4.5;
    let law = Config { law: LawKind::Linear, ..Config::DEFAULT };
    // The touch's hold alone (record version 5): one byte and the CRC.
    let hold = Config {
        press: touch_arm::config::settings::PressSettings { hold_cs: 50, ..Config::DEFAULT.press },
        ..Config::DEFAULT
    };
    // Hold to run alone (record version 7): the mode byte and the CRC.
    let mode = Config { hold_to_run: true, ..Config::DEFAULT };
    let all = vec![Config::DEFAULT, sample, speed, law, hold, mode];
    for c in &all {
        assert_eq!(c.validate(), Ok(()));
    }
    all
}

/// What a slot holds before the save.
#[derive(Clone, Copy, Debug)]
enum Slot {
    Blank,
    Valid(usize, u16),
    /// A valid record with one byte of the body flipped (CRC fails).
    Corrupt(usize, u16),
    /// A complete record whose commit byte is not `T`: what a save torn at its
    /// very last byte leaves. Its sequence is newer than anything else here.
    Uncommitted(usize, u16),
    /// A record of another layout version.
    Foreign(usize, u16),
    /// Random bytes.
    Garbage(u64),
}

fn fill(e: &mut SimEeprom, addr: u16, slot: Slot, cfgs: &[Config]) {
    let at = addr as usize;
    let bytes: Vec<u8> = match slot {
        Slot::Blank => vec![0xFF; RECORD_LEN],
        Slot::Valid(c, seq) => cfgs[c].encode(seq).to_vec(),
        Slot::Corrupt(c, seq) => {
            let mut r = cfgs[c].encode(seq);
            r[40] ^= 0x08;
            r.to_vec()
        }
        Slot::Uncommitted(c, seq) => {
            let mut r = cfgs[c].encode(seq);
            r[0] = UNCOMMITTED;
            r.to_vec()
        }
        Slot::Foreign(c, seq) => {
            let mut r = cfgs[c].encode(seq);
            r[2] = VERSION + 1;
            r.to_vec()
        }
        Slot::Garbage(seed) => {
            let mut rng = Rng::new(seed);
            (0..RECORD_LEN).map(|_| rng.below(256) as u8).collect()
        }
    };
    e.mem[at..at + RECORD_LEN].copy_from_slice(&bytes);
}

/// Prior contents of (A, B).
fn priors() -> Vec<(Slot, Slot)> {
    use Slot::*;
    vec![
        (Blank, Blank),
        (Valid(1, 4), Valid(1, 4)),
        // Equal sequence, different content: load takes A, so save must
        // write B first.
        (Valid(1, 4), Valid(0, 4)),
        (Valid(1, 9), Valid(3, 8)),
        (Valid(3, 8), Valid(1, 9)),
        (Valid(1, 0xFFFF), Valid(0, 0x0000)),
        (Valid(1, 5), Blank),
        (Blank, Valid(1, 5)),
        (Valid(1, 5), Corrupt(0, 6)),
        (Corrupt(0, 6), Valid(1, 5)),
        // A stale, newer body behind an uncommitted byte 0, beside the copy in use.
        (Valid(1, 5), Uncommitted(2, 6)),
        (Uncommitted(2, 6), Valid(1, 5)),
        (Uncommitted(2, 6), Uncommitted(3, 7)),
        (Foreign(2, 7), Valid(3, 3)),
        (Corrupt(1, 2), Corrupt(2, 3)),
        (Garbage(1), Valid(1, 1)),
        (Valid(2, 200), Garbage(2)),
        (Garbage(3), Garbage(4)),
    ]
}

#[test]
fn a_power_loss_at_any_byte_of_a_save_loads_the_old_or_the_new_configuration() {
    let cfgs = configs();
    let mut cases = 0u64;
    let mut loaded_new = 0u64;
    for (pa, pb) in priors() {
        let mut prior = SimEeprom::new();
        fill(&mut prior, SLOT_A_ADDR, pa, &cfgs);
        fill(&mut prior, SLOT_B_ADDR, pb, &cfgs);
        let before = load(&mut prior.clone());
        for new in &cfgs {
            // The bytes the complete save writes, in order.
            let mut dry = prior.clone();
            let mut rec = Recorder { inner: &mut dry, writes: Vec::new() };
            let seq = save(&mut rec, new).expect("a save without power loss succeeds");
            let writes = rec.writes;
            let first_slot = writes[0].0 / SLOT_B_ADDR * SLOT_B_ADDR;
            let first_len = writes.iter().take_while(|(a, _)| a / SLOT_B_ADDR * SLOT_B_ADDR == first_slot).count();
            // The first copy written is the one load does not pick.
            let picked = match before.source {
                Source::SlotA => Some(SLOT_A_ADDR),
                Source::SlotB => Some(SLOT_B_ADDR),
                Source::Defaults => None,
            };
            assert_ne!(Some(first_slot), picked, "prior ({pa:?}, {pb:?}): first write goes to the slot in use");
            for cut in 0..=writes.len() {
                let (addr, new_byte) = writes.get(cut).copied().unwrap_or((0, 0));
                let old_byte = prior.mem[addr as usize];
                for torn in [0x00, 0xFF, MAGIC[0], old_byte, new_byte, 0xA5] {
                    let mut e = prior.clone();
                    e.power_loss_after(cut);
                    e.torn_value = torn;
                    let _ = save(&mut e, new);
                    e.restore_power();
                    let l = load(&mut e);
                    let ctx = format!("prior ({pa:?}, {pb:?}), cut {cut} of {}, torn {torn:#04x}", writes.len());
                    let is_new = (l.config, l.seq) == (*new, seq) && l.source != Source::Defaults;
                    let is_old = (l.config, l.seq, l.source) == (before.config, before.seq, before.source);
                    assert!(is_new || is_old, "{ctx}: loaded {l:?}, neither the old nor the new configuration");
                    loaded_new += u64::from(is_new);
                    if cut >= first_len {
                        assert_eq!((l.config, l.seq), (*new, seq), "{ctx}: the first copy was complete");
                    }
                    // The next save repairs both copies.
                    let again = save(&mut e, &cfgs[0]).unwrap_or_else(|err| panic!("{ctx}: {err:?}"));
                    let l = load(&mut e);
                    assert_eq!((l.config, l.seq, l.warning), (cfgs[0], again, None), "{ctx}");
                    cases += 1;
                }
            }
        }
    }
    eprintln!("{cases} torn saves, {loaded_new} of them loaded the new configuration");
    assert!(cases > 40_000 && loaded_new > 10_000);
}

#[test]
fn load_and_save_agree_on_which_copy_is_in_use() {
    let cfgs = configs();
    for (pa, pb) in priors() {
        let mut e = SimEeprom::new();
        fill(&mut e, SLOT_A_ADDR, pa, &cfgs);
        fill(&mut e, SLOT_B_ADDR, pb, &cfgs);
        let l = load(&mut e);
        let a = Config::decode(e.mem[..RECORD_LEN].try_into().unwrap());
        let b = Config::decode(e.mem[SLOT_B_ADDR as usize..][..RECORD_LEN].try_into().unwrap());
        assert_eq!(pick(&a, &b).unwrap_or(Source::Defaults), l.source, "({pa:?}, {pb:?})");
        // Equal sequence numbers: A.
        if let (Ok(ra), Ok(rb)) = (&a, &b) {
            if ra.seq == rb.seq {
                assert_eq!(l.source, Source::SlotA);
            }
        }
    }
}

/// The saved poses (`config::poses`) are stored the same way: a power loss
/// at any byte of a pose save, with every kind of value in the torn byte,
/// from blank, equal, unequal, corrupt and uncommitted copies, loads the
/// poses before the save or the new ones, and the new ones once the first
/// copy is complete. The configuration's slots are never written.
#[test]
fn a_power_loss_at_any_byte_of_a_pose_save_loads_the_old_or_the_new_poses() {
    use touch_arm::config::poses::{self, Pose, Poses, POSE_RECORD_LEN, POSE_SLOT_A, POSE_SLOT_B};
    let mut one = Poses::EMPTY;
    assert!(one.set(1, Some(Pose { joints: [9000, 9000, -9000], grip: Some(0) })));
    let mut two = one;
    assert!(two.set(3, Some(Pose { joints: [4500, 10_000, -12_000], grip: None })));
    let mut moved = two;
    // One angle one hundredth of a degree apart: a record differing in a byte.
    assert!(moved.set(3, Some(Pose { joints: [4500, 10_000, -12_000], grip: Some(1) })));
    let sets = [Poses::EMPTY, one, two, moved];
    #[derive(Clone, Copy, Debug)]
    enum P {
        Blank,
        Valid(usize, u16),
        Corrupt(usize, u16),
        Uncommitted(usize, u16),
    }
    let fill = |e: &mut SimEeprom, at: u16, p: P| {
        let bytes = match p {
            P::Blank => vec![0xFF; POSE_RECORD_LEN],
            P::Valid(k, seq) => sets[k].encode(seq).to_vec(),
            P::Corrupt(k, seq) => {
                let mut r = sets[k].encode(seq);
                r[20] ^= 0x10;
                r.to_vec()
            }
            P::Uncommitted(k, seq) => {
                let mut r = sets[k].encode(seq);
                r[0] = UNCOMMITTED;
                r.to_vec()
            }
        };
        e.mem[at as usize..at as usize + POSE_RECORD_LEN].copy_from_slice(&bytes);
    };
    use P::*;
    let priors = [
        (Blank, Blank),
        (Valid(1, 4), Valid(1, 4)),
        (Valid(2, 4), Valid(1, 4)),
        (Valid(1, 9), Valid(2, 8)),
        (Valid(1, 0xFFFF), Valid(2, 0)),
        (Valid(2, 5), Corrupt(1, 6)),
        (Corrupt(1, 6), Valid(2, 5)),
        (Valid(1, 5), Uncommitted(3, 6)),
        (Uncommitted(3, 6), Valid(1, 5)),
    ];
    let mut cases = 0u64;
    for (pa, pb) in priors {
        let mut prior = SimEeprom::new();
        fill(&mut prior, POSE_SLOT_A, pa);
        fill(&mut prior, POSE_SLOT_B, pb);
        let before = poses::load(&mut prior.clone());
        for new in &sets {
            let mut dry = prior.clone();
            let mut rec = Recorder { inner: &mut dry, writes: Vec::new() };
            let seq = poses::save(&mut rec, new).expect("a save without power loss succeeds");
            let writes = rec.writes;
            assert!(writes.iter().all(|(a, _)| *a >= POSE_SLOT_A), "a configuration byte written");
            let slot_of = |a: u16| if a >= POSE_SLOT_B { POSE_SLOT_B } else { POSE_SLOT_A };
            let first_len = writes.iter().take_while(|(a, _)| slot_of(*a) == slot_of(writes[0].0)).count();
            for cut in 0..=writes.len() {
                let (addr, new_byte) = writes.get(cut).copied().unwrap_or((0, 0));
                let old_byte = prior.mem[addr as usize];
                for torn in [0x00, 0xFF, MAGIC[0], old_byte, new_byte, 0xA5] {
                    let mut e = prior.clone();
                    e.power_loss_after(cut);
                    e.torn_value = torn;
                    let _ = poses::save(&mut e, new);
                    e.restore_power();
                    let l = poses::load(&mut e);
                    let ctx = format!("prior ({pa:?}, {pb:?}), cut {cut} of {}, torn {torn:#04x}", writes.len());
                    let is_new = (l.poses, l.seq) == (*new, seq) && l.source != Source::Defaults;
                    let is_old = (l.poses, l.seq, l.source) == (before.poses, before.seq, before.source);
                    assert!(is_new || is_old, "{ctx}: loaded {l:?}");
                    if cut >= first_len {
                        assert_eq!((l.poses, l.seq), (*new, seq), "{ctx}: the first copy was complete");
                    }
                    let again = poses::save(&mut e, &sets[2]).unwrap_or_else(|err| panic!("{ctx}: {err:?}"));
                    let l = poses::load(&mut e);
                    assert_eq!((l.poses, l.seq, l.damaged), (sets[2], again, false), "{ctx}");
                    cases += 1;
                }
            }
        }
    }
    eprintln!("{cases} torn pose saves");
    assert!(cases > 10_000);
}

/// The pose record's layout (version 2, the gripper's angle per pose) and
/// its migration: a version-1 record (three joints per pose, CRC at 57), as
/// the firmware before the gripper wrote it, loads with no gripper angle,
/// and the next save writes version 2; and what decode refuses.
#[test]
fn pose_records_of_version_1_load_without_a_gripper_angle() {
    use touch_arm::config::crc::crc16;
    use touch_arm::config::poses::{self, Pose, Poses, POSE_RECORD_LEN, POSE_RECORD_LEN_V1, POSE_SLOT_A};
    // Version 1 written out here: magic, version, seq 7, slot 2 used with
    // (30, 120, -150) deg, the others unused, CRC of bytes 0..57.
    let mut v1 = vec![b'T', b'P', 1, 7, 0];
    for k in 0..4 {
        if k == 1 {
            v1.push(1);
            for v in [3000i32, 12_000, -15_000] {
                v1.extend_from_slice(&v.to_le_bytes());
            }
        } else {
            v1.extend_from_slice(&[0; 13]);
        }
    }
    let crc = crc16(&v1);
    v1.extend_from_slice(&crc.to_le_bytes());
    assert_eq!(v1.len(), POSE_RECORD_LEN_V1);
    let mut e = SimEeprom::new();
    e.mem[POSE_SLOT_A as usize..POSE_SLOT_A as usize + v1.len()].copy_from_slice(&v1);
    let l = poses::load(&mut e);
    let old = Pose { joints: [3000, 12_000, -15_000], grip: None };
    assert_eq!((l.source, l.seq, l.poses.get(2)), (Source::SlotA, 7, Some(old)));
    // The next save writes version 2 (to B first), keeping the old pose as it was.
    let mut next = l.poses;
    assert!(next.set(1, Some(Pose { joints: [9000, 9000, -9000], grip: Some(4500) })));
    assert_eq!(poses::save(&mut e, &next), Ok(8));
    let l = poses::load(&mut e);
    assert_eq!((l.poses, l.seq, l.damaged), (next, 8, false));
    let r = next.encode(8);
    assert_eq!(&r[..3], b"TP\x02");
    // Slot 1: flags 3 (used, with a gripper angle), the joints, 45 deg.
    assert_eq!(r[5], 3);
    assert_eq!(&r[18..22], &4500i32.to_le_bytes());
    // Slot 2: flags 1 (used, no gripper angle), its gripper word 0.
    assert_eq!((r[22], &r[35..39]), (1, &[0u8; 4][..]));
    assert_eq!(Poses::decode(&r), Ok((8, next)));
    // A gripper word without its flag, an unknown flag, a gripper beyond
    // 360 deg: refused even under a valid CRC.
    let reseal = |mut b: [u8; POSE_RECORD_LEN]| {
        let crc = crc16(&b[..POSE_RECORD_LEN - 2]);
        b[POSE_RECORD_LEN - 2..].copy_from_slice(&crc.to_le_bytes());
        b
    };
    let mut bad = r;
    bad[35] = 1;
    assert_eq!(Poses::decode(&reseal(bad)), Err(RecordError::Invalid));
    let mut bad = r;
    bad[5] = 7;
    assert_eq!(Poses::decode(&reseal(bad)), Err(RecordError::Invalid));
    let mut bad = r;
    bad[18..22].copy_from_slice(&36_001i32.to_le_bytes());
    assert_eq!(Poses::decode(&reseal(bad)), Err(RecordError::Invalid));
    let mut bad = r;
    bad[2] = 3;
    assert_eq!(Poses::decode(&bad), Err(RecordError::Version(3)));
}

/// The gripper's calibration (`config::grip`) is stored the same way: a
/// power loss at any byte of its save, with every kind of value in the torn
/// byte, from blank, equal, unequal, corrupt and uncommitted copies, loads
/// the calibration before the save or the new one, and the new one once the
/// first copy is complete. Neither the configuration's nor the poses' slots
/// are written.
#[test]
fn a_power_loss_at_any_byte_of_a_grip_save_loads_the_old_or_the_new_calibration() {
    use touch_arm::config::grip::{self, GRIP_DEFAULT, GRIP_RECORD_LEN, GRIP_SLOT_A, GRIP_SLOT_B};
    use touch_arm::servo::map::JointCal;
    let wide = JointCal { max_us: 2400, max_rad: std::f32::consts::PI, ..GRIP_DEFAULT };
    // One pulse limit a microsecond apart: a record differing in a byte.
    let nudged = JointCal { max_us: 1501, ..GRIP_DEFAULT };
    let slow = JointCal { max_speed_rad_s: 1.0, offset_us: 650.0, ..GRIP_DEFAULT };
    let sets = [GRIP_DEFAULT, wide, nudged, slow];
    #[derive(Clone, Copy, Debug)]
    enum P {
        Blank,
        Valid(usize, u16),
        Corrupt(usize, u16),
        Uncommitted(usize, u16),
    }
    let fill = |e: &mut SimEeprom, at: u16, p: P| {
        let bytes = match p {
            P::Blank => vec![0xFF; GRIP_RECORD_LEN],
            P::Valid(k, seq) => grip::encode(&sets[k], seq).to_vec(),
            P::Corrupt(k, seq) => {
                let mut r = grip::encode(&sets[k], seq);
                r[14] ^= 0x10;
                r.to_vec()
            }
            P::Uncommitted(k, seq) => {
                let mut r = grip::encode(&sets[k], seq);
                r[0] = UNCOMMITTED;
                r.to_vec()
            }
        };
        e.mem[at as usize..at as usize + GRIP_RECORD_LEN].copy_from_slice(&bytes);
    };
    use P::*;
    let priors = [
        (Blank, Blank),
        (Valid(1, 4), Valid(1, 4)),
        (Valid(2, 4), Valid(1, 4)),
        (Valid(1, 9), Valid(2, 8)),
        (Valid(1, 0xFFFF), Valid(2, 0)),
        (Valid(2, 5), Corrupt(1, 6)),
        (Corrupt(1, 6), Valid(2, 5)),
        (Valid(1, 5), Uncommitted(3, 6)),
        (Uncommitted(3, 6), Valid(1, 5)),
    ];
    let mut cases = 0u64;
    for (pa, pb) in priors {
        let mut prior = SimEeprom::new();
        fill(&mut prior, GRIP_SLOT_A, pa);
        fill(&mut prior, GRIP_SLOT_B, pb);
        let before = grip::load(&mut prior.clone());
        for new in &sets {
            let mut dry = prior.clone();
            let mut rec = Recorder { inner: &mut dry, writes: Vec::new() };
            let seq = grip::save(&mut rec, new).expect("a save without power loss succeeds");
            let writes = rec.writes;
            assert!(writes.iter().all(|(a, _)| *a >= GRIP_SLOT_A), "a configuration or pose byte written");
            let slot_of = |a: u16| if a >= GRIP_SLOT_B { GRIP_SLOT_B } else { GRIP_SLOT_A };
            let first_len = writes.iter().take_while(|(a, _)| slot_of(*a) == slot_of(writes[0].0)).count();
            for cut in 0..=writes.len() {
                let (addr, new_byte) = writes.get(cut).copied().unwrap_or((0, 0));
                let old_byte = prior.mem[addr as usize];
                for torn in [0x00, 0xFF, MAGIC[0], old_byte, new_byte, 0xA5] {
                    let mut e = prior.clone();
                    e.power_loss_after(cut);
                    e.torn_value = torn;
                    let _ = grip::save(&mut e, new);
                    e.restore_power();
                    let l = grip::load(&mut e);
                    let ctx = format!("prior ({pa:?}, {pb:?}), cut {cut} of {}, torn {torn:#04x}", writes.len());
                    let is_new = (l.cal, l.seq) == (*new, seq) && l.source != Source::Defaults;
                    let is_old = (l.cal, l.seq, l.source) == (before.cal, before.seq, before.source);
                    assert!(is_new || is_old, "{ctx}: loaded {l:?}");
                    if cut >= first_len {
                        assert_eq!((l.cal, l.seq), (*new, seq), "{ctx}: the first copy was complete");
                    }
                    let again = grip::save(&mut e, &sets[1]).unwrap_or_else(|err| panic!("{ctx}: {err:?}"));
                    let l = grip::load(&mut e);
                    assert_eq!((l.cal, l.seq, l.damaged), (sets[1], again, false), "{ctx}");
                    cases += 1;
                }
            }
        }
    }
    eprintln!("{cases} torn grip saves");
    assert!(cases > 5_000);
}

/// The gripper record's layout: the documented offsets, the defaults
/// round-trip bit for bit, and what load refuses.
#[test]
fn the_grip_record_round_trips_and_refuses_what_it_should() {
    use touch_arm::config::grip::{self, GRIP_DEFAULT, GRIP_RECORD_LEN, GRIP_SLOT_A};
    let r = grip::encode(&GRIP_DEFAULT, 0x1234);
    assert_eq!(&r[..5], &[b'T', b'G', 1, 0x34, 0x12]);
    assert_eq!(&r[5..9], &600.0f32.to_le_bytes());
    assert_eq!(&r[13..17], &[0x58, 0x02, 0xDC, 0x05], "600 and 1500 us");
    assert_eq!(grip::decode(&r), Ok((0x1234, GRIP_DEFAULT)));
    let mut bad = r;
    bad[2] = 2;
    assert_eq!(grip::decode(&bad), Err(RecordError::Version(2)));
    let mut bad = r;
    bad[GRIP_RECORD_LEN - 1] ^= 1;
    assert_eq!(grip::decode(&bad), Err(RecordError::Crc));
    // A valid CRC over an invalid calibration (min_us above max_us).
    let inverted = touch_arm::servo::map::JointCal { min_us: 1600, ..GRIP_DEFAULT };
    assert_eq!(grip::decode(&grip::encode(&inverted, 1)), Err(RecordError::Invalid));
    // Never written: the defaults, not reported as damage; one copy damaged is.
    let mut e = SimEeprom::new();
    assert_eq!(
        grip::load(&mut e),
        grip::LoadedGrip { cal: GRIP_DEFAULT, source: Source::Defaults, seq: 0, damaged: false }
    );
    e.mem[GRIP_SLOT_A as usize..GRIP_SLOT_A as usize + GRIP_RECORD_LEN].copy_from_slice(&bad);
    let l = grip::load(&mut e);
    assert!(l.damaged && l.source == Source::Defaults);
}

/// The display overrides (`config::lcd`) are stored the same way: a power
/// loss at any byte of their save, with every kind of value in the torn
/// byte, from blank, equal, unequal, corrupt and uncommitted copies, loads
/// the overrides before the save or the new ones, and the new ones once the
/// first copy is complete. No byte outside their two slots is written (the
/// configuration's, the poses' and the gripper's records stay as they were).
#[test]
fn a_power_loss_at_any_byte_of_an_lcd_save_loads_the_old_or_the_new_overrides() {
    use touch_arm::config::lcd::{self, LcdChoice, LcdSettings, LCD_DEFAULT, LCD_RECORD_LEN, LCD_SLOT_A, LCD_SLOT_B};
    let forced = LcdSettings { controller: LcdChoice::St7796, ..LCD_DEFAULT };
    // One flag apart: a record differing in one byte (and its CRC).
    let inverted = LcdSettings { invert: true, ..forced };
    let all = LcdSettings { controller: LcdChoice::Ili9325, invert: true, rotate_180: true };
    let sets = [LCD_DEFAULT, forced, inverted, all];
    let cases = torn_two_copy_saves!(lcd, LCD_RECORD_LEN, LCD_SLOT_A, LCD_SLOT_B, sets, (5, 0x01), "overrides' slots");
    eprintln!("{cases} torn lcd saves");
    // 9 priors × 4 records × (9 or 10 bytes a slot, twice, + the uncut
    // save) × 6 torn values.
    assert!(cases > 4_000);
}

/// The overrides' record layout: the documented offsets, and what load
/// refuses (each refusal leaves the defaults: probe, no inversion, no turn).
#[test]
fn the_lcd_record_round_trips_and_refuses_what_it_should() {
    use touch_arm::config::lcd::{self, LcdChoice, LcdSettings, LCD_DEFAULT, LCD_RECORD_LEN, LCD_SLOT_A};
    let s = LcdSettings { controller: LcdChoice::St7796, invert: false, rotate_180: true };
    let r = lcd::encode(&s, 0x1234);
    assert_eq!(&r[..7], &[b'T', b'L', 1, 0x34, 0x12, 5, 0b10]);
    assert_eq!(lcd::decode(&r), Ok((0x1234, s)));
    for (k, c) in LcdChoice::ALL.into_iter().enumerate() {
        assert_eq!(c as usize, k);
        assert_eq!(
            lcd::decode(&lcd::encode(&LcdSettings { controller: c, ..LCD_DEFAULT }, 1)).unwrap().1.controller,
            c
        );
    }
    let mut bad = r;
    bad[2] = 2;
    assert_eq!(lcd::decode(&bad), Err(RecordError::Version(2)));
    let mut bad = r;
    bad[LCD_RECORD_LEN - 1] ^= 1;
    assert_eq!(lcd::decode(&bad), Err(RecordError::Crc));
    // A valid CRC over an unknown controller id or an unknown flag.
    for (at, v) in [(5, 6), (6, 0b100)] {
        let mut odd = r;
        odd[at] = v;
        let crc = touch_arm::config::crc::crc16(&odd[..LCD_RECORD_LEN - 2]).to_le_bytes();
        odd[LCD_RECORD_LEN - 2..].copy_from_slice(&crc);
        assert_eq!(lcd::decode(&odd), Err(RecordError::Invalid), "byte {at} = {v}");
    }
    // Never written, or damaged: the defaults.
    let mut e = SimEeprom::new();
    assert_eq!(lcd::load(&mut e), (Source::Defaults, 0, LCD_DEFAULT));
    e.mem[LCD_SLOT_A as usize..LCD_SLOT_A as usize + LCD_RECORD_LEN].copy_from_slice(&bad);
    assert_eq!(lcd::load(&mut e), (Source::Defaults, 0, LCD_DEFAULT));
}
