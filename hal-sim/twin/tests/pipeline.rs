//! Host tests for the input/output pipeline modules: touch filter, servo
//! mapping, configuration store + CRC, and the serial command protocol.

use proptest::prelude::*;

fn cfg() -> ProptestConfig {
    ProptestConfig::with_cases(256)
}

mod touch {
    use super::*;
    use hal_sim::rng::Rng;
    use touch_arm::seam::RawSample;
    use touch_arm::touch::filter::*;

    const C: FilterConfig = FilterConfig::DEFAULT;

    fn filter() -> TouchFilter {
        TouchFilter::new(&C).unwrap()
    }

    /// A read of 5 identical samples.
    fn steady(x: u16, y: u16, z: u16) -> [RawSample; 5] {
        [RawSample { x, y, z, z1: 0 }; 5]
    }

    fn idle() -> [RawSample; 5] {
        steady(0, 0, 3)
    }

    fn pt(x: u16, y: u16) -> TouchPoint {
        TouchPoint { x, y }
    }

    /// Uniform in -r..=r.
    fn noise(rng: &mut Rng, r: i32) -> i32 {
        rng.below(2 * r as u64 + 1) as i32 - r
    }

    #[test]
    fn median_small_cases() {
        assert_eq!(median_u16(&mut [5]), 5);
        assert_eq!(median_u16(&mut [9, 1, 5]), 5);
        assert_eq!(median_u16(&mut [7, 7, 1, 7, 1]), 7);
        assert_eq!(median_u16(&mut [1023, 0, 1023, 0, 512]), 512);
        // Even length: the upper middle; empty: 0.
        assert_eq!(median_u16(&mut [4, 1, 3, 2]), 3);
        assert_eq!(median_u16(&mut []), 0);
    }

    proptest! {
        #![proptest_config(cfg())]
        #[test]
        fn median_matches_sort(v in prop::collection::vec(any::<u16>(), 1..=15)) {
            let mut sorted = v.clone();
            sorted.sort_unstable();
            let mut work = v.clone();
            let m = median_u16(&mut work);
            prop_assert_eq!(m, sorted[v.len() / 2]);
            // It sorts in place (the filter relies on that for the spread).
            prop_assert_eq!(work, sorted);
        }
    }

    #[test]
    fn pressure_measure() {
        // Untouched: plates disconnected, z1 at ground, z2 at the rail.
        assert_eq!(pressure(0, 1023), 0);
        assert_eq!(pressure(300, 700), 1023 + 300 - 700);
        assert_eq!(pressure(1023, 0), 2046);
        // Out-of-range ADC values are clamped, never overflow.
        assert_eq!(pressure(u16::MAX, 0), 2046);
        assert_eq!(pressure(0, u16::MAX), 0);
        // Monotone: firmer touch raises z1 and lowers z2.
        for z1 in (0..1024).step_by(31) {
            for z2 in (0..1024).step_by(37) {
                assert!(pressure(z1 + 1, z2) > pressure(z1, z2) || z1 + 1 > 1023);
                if z2 > 0 {
                    assert!(pressure(z1, z2 - 1) > pressure(z1, z2));
                }
            }
        }
    }

    #[test]
    fn config_validation() {
        assert_eq!(C.validate(), Ok(()));
        for n in [0u8, 2, 4, 10, 11] {
            let c = FilterConfig { samples: n, ..C };
            assert_eq!(c.validate(), Err(FilterConfigError::SampleCount), "n = {n}");
        }
        for n in [1u8, 3, 7, 9] {
            assert_eq!(FilterConfig { samples: n, ..C }.validate(), Ok(()));
        }
        let bad_window = [(0u16, 1000u16), (500, 499)];
        for (z_min, z_max) in bad_window {
            let c = FilterConfig { z_min, z_max, ..C };
            assert_eq!(c.validate(), Err(FilterConfigError::PressureWindow));
        }
        assert_eq!(FilterConfig { press_confirm: 1, ..C }.validate(), Err(FilterConfigError::Confirm));
        assert_eq!(FilterConfig { release_confirm: 1, ..C }.validate(), Err(FilterConfigError::Confirm));
        assert!(TouchFilter::new(&FilterConfig { samples: 4, ..C }).is_err());
    }

    #[test]
    fn classify_basics() {
        let f = filter();
        // Medians per axis, a single spike in each axis is removed.
        let mut s = steady(500, 600, 400);
        s[0].x = 510;
        s[1].x = 495;
        s[4].y = 615;
        s[2].z = 420;
        // z1 = 0: no plate ratio (`u16::MAX`).
        assert_eq!(f.classify(&s), Read::Touched { point: pt(500, 600), z: 400, plate: u16::MAX });
        assert_eq!(f.classify(&s[..4]), Read::Rejected(Reject::SampleCount));
        assert_eq!(f.classify(&[]), Read::Rejected(Reject::SampleCount));
        assert_eq!(f.classify(&idle()), Read::NotTouched(NoTouch::PressureLow));
        assert_eq!(f.classify(&steady(500, 500, 1500)), Read::NotTouched(NoTouch::PressureHigh));
        // Window edges are inclusive.
        assert!(matches!(f.classify(&steady(1, 2, C.z_min)), Read::Touched { .. }));
        assert!(matches!(f.classify(&steady(1, 2, C.z_max)), Read::Touched { .. }));
        assert_eq!(f.classify(&steady(1, 2, C.z_min - 1)), Read::NotTouched(NoTouch::PressureLow));
        // One sample lifting off: partial contact, not a point.
        let mut s = steady(500, 600, 400);
        s[3].z = 10;
        assert_eq!(f.classify(&s), Read::Rejected(Reject::PartialContact));
    }

    #[test]
    fn spread_rejection() {
        let f = filter();
        let base = steady(500, 600, 400);
        // Spread exactly at the limit passes, one more count fails, per axis.
        let mut s = base;
        s[0].x = 500 - C.max_spread / 2;
        s[1].x = 500 + C.max_spread / 2;
        assert!(matches!(f.classify(&s), Read::Touched { .. }));
        s[1].x += 1;
        assert_eq!(f.classify(&s), Read::Rejected(Reject::SpreadX));
        let mut s = base;
        s[2].y = 600 + C.max_spread + 1;
        assert_eq!(f.classify(&s), Read::Rejected(Reject::SpreadY));
        // A spike the median would hide is still rejected: the voltage had not settled.
        let mut s = base;
        s[4].x = 900;
        assert_eq!(f.classify(&s), Read::Rejected(Reject::SpreadX));
    }

    #[test]
    fn noisy_press_converges_to_true_point() {
        let mut rng = Rng::new(7);
        for _trial in 0..200 {
            let (tx, ty) = (100 + rng.below(800), 100 + rng.below(800));
            let mut f = filter();
            let mut pressed = None;
            for read in 0..C.press_confirm as usize {
                let mut s = [RawSample { x: 0, y: 0, z: 0, z1: 0 }; 5];
                for v in s.iter_mut() {
                    v.x = (tx as i32 + noise(&mut rng, 3)) as u16;
                    v.y = (ty as i32 + noise(&mut rng, 3)) as u16;
                    v.z = (500 + noise(&mut rng, 200)) as u16;
                }
                let step = f.update(&s);
                assert!(matches!(step.read, Read::Touched { .. }));
                if read + 1 < C.press_confirm as usize {
                    assert_eq!(step.event, None);
                } else {
                    pressed = step.event;
                }
            }
            let Some(TouchEvent::Pressed(p)) = pressed else {
                panic!("no press after {} stable reads", C.press_confirm)
            };
            assert!(p.x.abs_diff(tx as u16) <= 3 && p.y.abs_diff(ty as u16) <= 3, "{p:?} vs {tx},{ty}");
            assert_eq!(f.held(), Some(p));
        }
    }

    #[test]
    fn pressed_point_is_the_mean_of_the_stable_run() {
        let mut f = filter();
        assert_eq!(f.update(&steady(500, 300, 400)).event, None);
        assert_eq!(f.update(&steady(504, 302, 400)).event, None);
        // (500 + 504 + 507) / 3 = 503.67 → 504; (300 + 302 + 306) / 3 = 302.67 → 303.
        assert_eq!(f.update(&steady(507, 306, 400)).event, Some(TouchEvent::Pressed(pt(504, 303))));
    }

    #[test]
    fn landing_transient_is_not_the_target() {
        // The finger lands at (200, 200) sliding toward (600, 700) where it
        // rests; the partial-contact and sliding reads must not become the target.
        let mut f = filter();
        let mut s = steady(200, 200, 400);
        s[0].z = 50;
        assert_eq!(f.update(&s).read, Read::Rejected(Reject::PartialContact));
        for k in 1..=4u16 {
            let step = f.update(&steady(200 + 80 * k, 200 + 100 * k, 300));
            assert_eq!(step.event, None);
        }
        let mut events = vec![];
        for _ in 0..5 {
            events.extend(f.update(&steady(600, 700, 450)).event);
        }
        assert_eq!(events, vec![TouchEvent::Pressed(pt(600, 700))]);
    }

    #[test]
    fn press_needs_n_consecutive_stable_reads() {
        let n = C.press_confirm as usize;
        let mut f = filter();
        // n − 1 stable reads, then a dropout: the run starts over.
        for _ in 0..n - 1 {
            assert_eq!(f.update(&steady(400, 400, 400)).event, None);
        }
        assert_eq!(f.update(&idle()).event, None);
        for _ in 0..n - 1 {
            assert_eq!(f.update(&steady(400, 400, 400)).event, None);
        }
        // A rejected read also breaks the run.
        let mut spiky = steady(400, 400, 400);
        spiky[0].y = 0;
        assert_eq!(f.update(&spiky).event, None);
        for _ in 0..n - 1 {
            assert_eq!(f.update(&steady(400, 400, 400)).event, None);
        }
        assert_eq!(f.update(&steady(400, 400, 400)).event, Some(TouchEvent::Pressed(pt(400, 400))));
        // Reads hopping by more than the radius never confirm.
        let mut f = filter();
        for i in 0..50u16 {
            let x = if i % 2 == 0 { 300 } else { 300 + C.stability_radius + 1 };
            assert_eq!(f.update(&steady(x, 300, 400)).event, None);
        }
        let mut f = filter();
        for i in 0..50u16 {
            let y = if i % 2 == 0 { 300 } else { 300 - C.stability_radius - 1 };
            assert_eq!(f.update(&steady(300, y, 400)).event, None);
        }
        // Within the radius of each other (box ≤ radius): confirms.
        let r = C.stability_radius;
        let mut f = filter();
        f.update(&steady(300, 300, 400));
        f.update(&steady(300 + r, 300, 400));
        assert!(matches!(f.update(&steady(300, 300 + r, 400)).event, Some(TouchEvent::Pressed(_))));
    }

    #[test]
    fn release_hysteresis() {
        let m = C.release_confirm as usize;
        let mut f = filter();
        for _ in 0..C.press_confirm {
            f.update(&steady(400, 500, 400));
        }
        assert_eq!(f.held(), Some(pt(400, 500)));
        // A single dropout (and m − 1 of them) does not release.
        for gap in 1..m {
            for _ in 0..gap {
                assert_eq!(f.update(&idle()).event, None);
            }
            assert_eq!(f.update(&steady(400, 500, 400)).event, None);
            assert_eq!(f.held(), Some(pt(400, 500)));
        }
        // Rejected reads count like dropouts; m in a row release exactly once.
        let mut partial = steady(400, 500, 400);
        partial[0].z = 0;
        for i in 0..m {
            let read = if i % 2 == 0 { partial } else { idle() };
            let ev = f.update(&read).event;
            if i + 1 < m {
                assert_eq!(ev, None);
            } else {
                assert_eq!(ev, Some(TouchEvent::Released));
            }
        }
        assert_eq!(f.held(), None);
        for _ in 0..20 {
            assert_eq!(f.update(&idle()).event, None);
        }
        // And a new press works after the release.
        let evs: Vec<_> = (0..C.press_confirm).filter_map(|_| f.update(&steady(100, 900, 400)).event).collect();
        assert_eq!(evs, vec![TouchEvent::Pressed(pt(100, 900))]);
    }

    #[test]
    fn drag_reports_resting_points_only() {
        let mut f = filter();
        for _ in 0..C.press_confirm {
            f.update(&steady(400, 400, 400));
        }
        // Jitter within the radius: nothing.
        for i in 0..30u16 {
            let ev = f.update(&steady(400 + i % 5, 400 + (i * 3) % 7, 400)).event;
            assert_eq!(ev, None);
        }
        // A dropout, then resting again within the radius of the held point:
        // a new stable run, but not a move.
        let r = C.stability_radius;
        for (dx, dy) in [(r, 0), (0, r), (r, r)] {
            f.update(&idle());
            for _ in 0..C.press_confirm + 2 {
                assert_eq!(f.update(&steady(400 + dx, 400 + dy, 400)).event, None);
            }
        }
        assert_eq!(f.held(), Some(pt(400, 400)));
        // Slide (each read far from the last): nothing until it rests.
        for k in 1..=5u16 {
            assert_eq!(f.update(&steady(400 + 40 * k, 400, 400)).event, None);
        }
        let mut evs = vec![];
        for _ in 0..10 {
            evs.extend(f.update(&steady(700, 420, 400)).event);
        }
        assert_eq!(evs, vec![TouchEvent::Moved(pt(700, 420))]);
        assert_eq!(f.held(), Some(pt(700, 420)));
        f.reset();
        assert_eq!(f.held(), None);
    }

    fn idle_sample() -> impl Strategy<Value = RawSample> {
        (any::<u16>(), any::<u16>(), 0..C.z_min).prop_map(|(x, y, z)| RawSample { x, y, z, z1: 0 })
    }

    /// Samples where at least one sample of each read is outside the window.
    fn broken_read() -> impl Strategy<Value = Vec<RawSample>> {
        (
            prop::collection::vec((0u16..1024, 0u16..1024, 0u16..2047), 5),
            0usize..5,
            prop_oneof![0..C.z_min, (C.z_max + 1)..2047],
        )
            .prop_map(|(v, k, zout)| {
                let mut s: Vec<_> = v.into_iter().map(|(x, y, z)| RawSample { x, y, z, z1: 0 }).collect();
                s[k].z = zout;
                s
            })
    }

    proptest! {
        #![proptest_config(cfg())]
        #[test]
        fn idle_noise_never_presses(reads in prop::collection::vec(prop::collection::vec(idle_sample(), 5), 1..60)) {
            let mut f = filter();
            for r in &reads {
                let step = f.update(r);
                prop_assert_eq!(step.read, Read::NotTouched(NoTouch::PressureLow));
                prop_assert_eq!(step.event, None);
            }
        }

        #[test]
        fn pressure_outside_window_never_yields_a_point(reads in prop::collection::vec(broken_read(), 1..60)) {
            let mut f = filter();
            for r in &reads {
                let step = f.update(r);
                let touched = matches!(step.read, Read::Touched { .. });
                prop_assert!(!touched);
                prop_assert_eq!(step.event, None);
            }
        }

        #[test]
        fn press_then_release_sequence(
            tx in 0u16..1024, ty in 0u16..1024,
            noise in prop::collection::vec((-3i32..=3, -3i32..=3), 5 * 6),
        ) {
            // Any point (incl. the panel edges) presses after exactly N reads
            // and releases after exactly M dropouts.
            let mut f = filter();
            let mut events = vec![];
            for read in noise.chunks(5).take(C.press_confirm as usize) {
                let s: Vec<_> = read.iter().map(|(dx, dy)| RawSample {
                    x: (tx as i32 + dx).clamp(0, 1023) as u16,
                    y: (ty as i32 + dy).clamp(0, 1023) as u16,
                    z: 600,
                    z1: 0,
                }).collect();
                events.extend(f.update(&s).event);
            }
            prop_assert_eq!(events.len(), 1);
            let TouchEvent::Pressed(p) = events[0] else { panic!() };
            prop_assert!(p.x.abs_diff(tx) <= 3 && p.y.abs_diff(ty) <= 3);
            for i in 0..C.release_confirm {
                let ev = f.update(&idle()).event;
                prop_assert_eq!(ev, if i + 1 == C.release_confirm { Some(TouchEvent::Released) } else { None });
            }
        }
    }
}

mod servo {
    use super::*;
    use std::f64::consts::PI;
    use touch_arm::servo::map::*;

    fn maps() -> [ServoMap; 3] {
        JointCal::DEFAULTS.map(|c| ServoMap::new(&c).unwrap())
    }

    #[test]
    fn defaults_are_valid_and_hit_expected_pulses() {
        let [base, shoulder, elbow] = maps();
        let us = |m: &ServoMap, a: f64| m.angle_to_pulse(a).unwrap();
        assert_eq!(us(&base, 0.0), Pulse { ticks: 1200, clamped: None });
        assert_eq!(us(&base, PI / 2.0).ticks, 3000);
        assert_eq!(us(&base, PI), Pulse { ticks: 4800, clamped: None });
        assert_eq!(us(&shoulder, PI / 4.0).ticks, 2100);
        assert_eq!(us(&elbow, 0.0), Pulse { ticks: 4800, clamped: None });
        assert_eq!(us(&elbow, -PI / 2.0).ticks, 3000);
        assert_eq!(us(&elbow, -PI), Pulse { ticks: 1200, clamped: None });
        // f32 path agrees.
        assert_eq!(base.angle_to_pulse(core::f32::consts::FRAC_PI_2).unwrap().ticks, 3000);
        // Float noise just past a limit is not reported as a clamp.
        assert_eq!(shoulder.angle_to_pulse(-1e-7f32).unwrap(), Pulse { ticks: 1200, clamped: None });
        assert_eq!(elbow.angle_to_pulse(1e-6f64).unwrap(), Pulse { ticks: 4800, clamped: None });
    }

    #[test]
    fn clamps_and_reports() {
        let [base, _, elbow] = maps();
        assert_eq!(base.angle_to_pulse(-0.1f64).unwrap(), Pulse { ticks: 1200, clamped: Some(Limit::AngleMin) });
        assert_eq!(base.angle_to_pulse(4.0f32).unwrap(), Pulse { ticks: 4800, clamped: Some(Limit::AngleMax) });
        assert_eq!(elbow.angle_to_pulse(0.5f32).unwrap(), Pulse { ticks: 4800, clamped: Some(Limit::AngleMax) });
        // Pulse limits narrower than the angle range: the pulse limit binds.
        let cal = JointCal { min_us: 1000, max_us: 2000, ..JointCal::BASE_DEFAULT };
        let m = ServoMap::new(&cal).unwrap();
        assert_eq!(m.angle_to_pulse(0.0f64).unwrap(), Pulse { ticks: 2000, clamped: Some(Limit::PulseMin) });
        assert_eq!(m.angle_to_pulse(3.0f64).unwrap(), Pulse { ticks: 4000, clamped: Some(Limit::PulseMax) });
        // Within half a µs of a pulse limit is rounding, not a clamp.
        let k = JointCal::BASE_DEFAULT.us_per_rad as f64;
        let at = |us: f64| (us - 600.0) / k;
        assert_eq!(m.angle_to_pulse(at(999.7)).unwrap(), Pulse { ticks: 2000, clamped: None });
        assert_eq!(m.angle_to_pulse(at(999.3)).unwrap(), Pulse { ticks: 2000, clamped: Some(Limit::PulseMin) });
        assert_eq!(m.angle_to_pulse(at(2000.4)).unwrap(), Pulse { ticks: 4000, clamped: None });
        assert_eq!(m.angle_to_pulse(at(2000.6)).unwrap(), Pulse { ticks: 4000, clamped: Some(Limit::PulseMax) });
        // Both act: the pulse limit (applied last) is reported.
        assert_eq!(m.angle_to_pulse(-5.0f64).unwrap(), Pulse { ticks: 2000, clamped: Some(Limit::PulseMin) });
        // Reversed direction: large angles give small pulses.
        let rev = JointCal { offset_us: 2400.0, us_per_rad: -1800.0 / core::f32::consts::PI, ..JointCal::BASE_DEFAULT };
        let m = ServoMap::new(&rev).unwrap();
        assert_eq!(m.angle_to_pulse(PI).unwrap().ticks, 1200);
        assert_eq!(m.angle_to_pulse(0.0f64).unwrap().ticks, 4800);
        assert_eq!(m.angle_to_pulse(9.0f64).unwrap(), Pulse { ticks: 1200, clamped: Some(Limit::AngleMax) });
    }

    #[test]
    fn non_finite_is_refused() {
        for m in maps() {
            for a in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -f32::NAN] {
                assert_eq!(m.angle_to_pulse(a), Err(ServoError::NotFinite));
            }
            assert_eq!(m.angle_to_pulse(f64::NAN), Err(ServoError::NotFinite));
        }
    }

    #[test]
    fn ticks() {
        assert_eq!(clamp_ticks(3001), 3001);
        assert_eq!(clamp_ticks(1000), 1000);
        assert_eq!(clamp_ticks(5000), 5000);
        // Never 0 (no pulse) nor ≥ TOP (output stuck high).
        assert_eq!(clamp_ticks(0), 1000);
        assert_eq!(clamp_ticks(u16::MAX), 5000);
        for t in 0..=u16::MAX {
            let c = clamp_ticks(t);
            assert!((1000..=5000).contains(&c) && c < TIMER5_TOP);
        }
        assert_eq!(Pulse { ticks: 2469, clamped: None }.us(), 1234.5);
        // Half a µs is resolved: 1500.5 µs on the base.
        let base = ServoMap::new(&JointCal::BASE_DEFAULT).unwrap();
        let k = JointCal::BASE_DEFAULT.us_per_rad as f64;
        assert_eq!(base.angle_to_pulse((1500.5 - 600.0) / k).unwrap().ticks, 3001);
        assert_eq!(base.angle_to_pulse((1500.3 - 600.0) / k).unwrap().ticks, 3001);
        assert_eq!(base.angle_to_pulse((1500.2 - 600.0) / k).unwrap().ticks, 3000);
        // 40000 ticks of 0.5 µs = 20 ms = 50 Hz.
        assert_eq!((TIMER5_TOP as u32 + 1) / TICKS_PER_US as u32, 20_000);
    }

    #[test]
    fn validation() {
        let b = JointCal::BASE_DEFAULT;
        let cases: &[(JointCal, JointCalError)] = &[
            (JointCal { offset_us: f32::NAN, ..b }, JointCalError::NotFinite),
            (JointCal { max_rad: f32::INFINITY, ..b }, JointCalError::NotFinite),
            (JointCal { max_speed_rad_s: f32::NAN, ..b }, JointCalError::NotFinite),
            (JointCal { min_us: 499, ..b }, JointCalError::PulseLimits),
            (JointCal { max_us: 2501, ..b }, JointCalError::PulseLimits),
            (JointCal { min_us: 1500, max_us: 1500, ..b }, JointCalError::PulseLimits),
            (JointCal { min_rad: 1.0, max_rad: 1.0, ..b }, JointCalError::AngleLimits),
            (JointCal { min_rad: -7.0, ..b }, JointCalError::AngleLimits),
            (JointCal { us_per_rad: 0.0, ..b }, JointCalError::Scale),
            (JointCal { us_per_rad: -99.0, ..b }, JointCalError::Scale),
            (JointCal { us_per_rad: 3001.0, ..b }, JointCalError::Scale),
            (JointCal { offset_us: 20001.0, ..b }, JointCalError::Offset),
            (JointCal { max_speed_rad_s: 0.0, ..b }, JointCalError::Speed),
            (JointCal { max_speed_rad_s: 51.0, ..b }, JointCalError::Speed),
            // 0..π maps to 2600..4400 µs: entirely above the 600..2400 range.
            (JointCal { offset_us: 2600.0, ..b }, JointCalError::NoOverlap),
        ];
        for (cal, err) in cases {
            assert_eq!(cal.validate(), Err(*err), "{cal:?}");
            assert_eq!(ServoMap::new(cal), Err(*err));
        }
        for cal in JointCal::DEFAULTS {
            assert_eq!(cal.validate(), Ok(()));
        }
    }

    /// Valid calibrations, built from independent draws and kept only if valid.
    fn any_cal() -> impl Strategy<Value = JointCal> {
        (
            prop_oneof![100.0f32..3000.0, -3000.0f32..-100.0],
            500u16..2500,
            1u16..2000,
            -6.0f32..6.0,
            0.01f32..6.0,
            0.1f32..50.0,
            0.0f32..=1.0,
            0.0f32..=1.0,
        )
            .prop_map(|(us_per_rad, min_us, w, min_rad, span, v, s, t)| {
                let max_us = (min_us + w).min(2500);
                let max_rad = (min_rad + span).min(MAX_ABS_ANGLE_RAD);
                // Some angle in range hits some pulse in range.
                let target = min_us as f32 + s * (max_us - min_us) as f32;
                let a = min_rad + t * (max_rad - min_rad);
                JointCal {
                    offset_us: target - us_per_rad * a,
                    us_per_rad,
                    min_us,
                    max_us,
                    min_rad,
                    max_rad,
                    max_speed_rad_s: v,
                    max_accel_rad_s2: 10.0 * v,
                }
            })
            .prop_filter("valid", |c| c.validate().is_ok())
    }

    fn any_angle_f32() -> impl Strategy<Value = f32> {
        prop_oneof![
            prop::num::f32::ANY,
            -10.0f32..10.0,
            Just(f32::NAN),
            Just(f32::INFINITY),
            Just(f32::NEG_INFINITY),
            Just(f32::MAX),
            Just(-f32::MAX),
        ]
    }

    proptest! {
        #![proptest_config(cfg())]
        #[test]
        fn never_exceeds_limits_f32(cal in any_cal(), a in any_angle_f32()) {
            let m = ServoMap::new(&cal).unwrap();
            match m.angle_to_pulse(a) {
                Ok(p) => {
                    prop_assert!(a.is_finite());
                    prop_assert!(p.ticks >= 2 * cal.min_us && p.ticks <= 2 * cal.max_us, "{p:?}");
                    prop_assert!(p.ticks >= 2 * ABS_MIN_US && p.ticks <= 2 * ABS_MAX_US);
                    // The pulse is the formula at the clamped angle, clamped, rounded.
                    let ac = (a as f64).clamp(cal.min_rad as f64, cal.max_rad as f64);
                    let raw = cal.offset_us as f64 + cal.us_per_rad as f64 * ac;
                    let want = raw.clamp(cal.min_us as f64, cal.max_us as f64);
                    prop_assert!((f64::from(p.us()) - want).abs() <= 0.25 + 1e-2, "{} vs {}", p.us(), want);
                    // No clamp reported iff the request was met to within 0.5 µs.
                    let unclamped = cal.offset_us as f64 + cal.us_per_rad as f64 * a as f64;
                    if (unclamped - want).abs() > 0.52 {
                        prop_assert!(p.clamped.is_some());
                    }
                    if (unclamped - want).abs() < 0.48 {
                        prop_assert_eq!(p.clamped, None);
                    }
                }
                Err(e) => {
                    prop_assert!(!a.is_finite());
                    prop_assert_eq!(e, ServoError::NotFinite);
                }
            }
        }

        #[test]
        fn never_exceeds_limits_f64(cal in any_cal(), a in prop::num::f64::ANY) {
            let m = ServoMap::new(&cal).unwrap();
            match m.angle_to_pulse(a) {
                Ok(p) => prop_assert!(p.ticks >= 2 * cal.min_us && p.ticks <= 2 * cal.max_us),
                Err(_) => prop_assert!(!a.is_finite()),
            }
        }

        #[test]
        fn round_trip(j in 0usize..3, t in 0.0f64..=1.0) {
            let m = maps()[j];
            let (lo, hi) = m.angle_limits::<f64>();
            let a = lo + (hi - lo) * t;
            let p = m.angle_to_pulse(a).unwrap();
            prop_assert_eq!(p.clamped, None);
            let back: f64 = m.pulse_to_angle(p.ticks);
            // Rounding to the 0.5 µs tick costs at most 0.25 µs of angle.
            let tol = 0.25 / m.cal().us_per_rad.abs() as f64 + 1e-6;
            prop_assert!((back - a).abs() <= tol, "{a} -> {} -> {back}", p.ticks);
            // And the other way: every pulse in range maps back onto itself.
            let ticks = 1200 + ((t * 3600.0) as u16);
            let ang: f32 = m.pulse_to_angle(ticks);
            prop_assert_eq!(m.angle_to_pulse(ang).unwrap().ticks, ticks);
        }
    }
}

mod config {
    use super::*;
    use embedded_storage::{ReadStorage, Storage};
    use hal_sim::devices::SimEeprom;
    use touch_arm::config::crc::*;
    use touch_arm::config::settings::*;
    use touch_arm::config::settings::{CalSet, JointField, TouchField};
    use touch_arm::config::store::*;
    use touch_arm::motion::plan::LawKind;
    use touch_arm::seam::StorageError;
    use touch_arm::servo::map::{Joint, JointCal, JointCalError};
    use touch_arm::touch::map::Calibration;
    use touch_arm::touch::wiring::Wiring;

    /// The simulator's EEPROM (erased = 0xFF, power loss after a number of
    /// written bytes), seen one record at a time.
    fn record(e: &mut SimEeprom, addr: u16) -> &mut [u8] {
        &mut e.mem[addr as usize..addr as usize + RECORD_LEN]
    }

    fn sample_config() -> Config {
        let mut c = Config::DEFAULT;
        c.joints[0].offset_us = 612.5;
        c.joints[1].us_per_rad = -600.25;
        c.joints[1].offset_us = 2500.0;
        c.joints[2].min_us = 700;
        c.joints[2].max_speed_rad_s = 4.5;
        c.touch = Calibration {
            x_min: 100,
            x_max: 950,
            y_min: 90,
            y_max: 900,
            swap_xy: true,
            invert_x: false,
            invert_y: true,
        };
        c.speed = SpeedPreset::Fast;
        c.law = LawKind::Quintic;
        c.wiring = Some(Wiring::C);
        c.lift_centi = Some(35);
        c.press = PressSettings { hold_cs: 25, repeat_cs: 50, radius: 90, plate: 431 };
        c.arm = ArmSettings { l2_cmm: 12_050, l3_cmm: 8_000, home: [9000, 4500, -13_500], park: [-1, 17_000, -32_767] };
        c.hold_to_run = true;
        assert_eq!(c.validate(), Ok(()));
        c
    }

    #[test]
    fn crc_check_values() {
        assert_eq!(crc16(b"123456789"), 0x29B1);
        assert_eq!(crc16(b""), 0xFFFF);
        assert_eq!(crc16(b"A"), 0xB915);
        let data = b"touch-arm configuration";
        for split in 0..data.len() {
            let (a, b) = data.split_at(split);
            assert_eq!(crc16_update(crc16_update(CRC16_INIT, a), b), crc16(data));
        }
    }

    proptest! {
        #![proptest_config(cfg())]
        /// Against a straightforward reference (reflect-free CCITT, MSB first).
        #[test]
        fn crc_matches_reference(data in prop::collection::vec(any::<u8>(), 0..64), pos in any::<prop::sample::Index>(), bit in 0u8..8) {
            let mut crc: u32 = 0xFFFF;
            for &b in &data {
                for i in (0..8).rev() {
                    let top = ((crc >> 15) & 1) ^ ((b as u32 >> i) & 1);
                    crc = (crc << 1) & 0xFFFF;
                    if top == 1 { crc ^= 0x1021; }
                }
            }
            prop_assert_eq!(crc16(&data) as u32, crc);
            // Any single-bit error changes the CRC.
            if !data.is_empty() {
                let mut d = data.clone();
                d[pos.index(data.len())] ^= 1 << bit;
                prop_assert_ne!(crc16(&d), crc16(&data));
            }
        }
    }

    #[test]
    fn layout_is_explicit_little_endian() {
        let c = sample_config();
        let r = c.encode(0x1234);
        assert_eq!(r.len(), RECORD_LEN);
        assert_eq!(&r[0..2], b"TA");
        assert_eq!(r[2], VERSION);
        assert_eq!(&r[3..5], &[0x34, 0x12]);
        assert_eq!(&r[5..9], &612.5f32.to_le_bytes());
        assert_eq!(&r[9..13], &c.joints[0].us_per_rad.to_le_bytes());
        assert_eq!(&r[13..15], &600u16.to_le_bytes());
        // Elbow min_us: joint 2 starts at 5 + 48, min_us at +8.
        assert_eq!(&r[61..63], &700u16.to_le_bytes());
        assert_eq!(&r[77..79], &100u16.to_le_bytes());
        assert_eq!(&r[83..85], &900u16.to_le_bytes());
        assert_eq!(r[85], 0b101); // swap | invert_y
        assert_eq!(r[86], SpeedPreset::Fast.id());
        assert_eq!(r[87], LawKind::Quintic.id());
        // Version 2 appends the acceleration limits before the CRC.
        assert_eq!(&r[88..92], &c.joints[0].max_accel_rad_s2.to_le_bytes());
        assert_eq!(&r[96..100], &c.joints[2].max_accel_rad_s2.to_le_bytes());
        // Version 3 appends the measured touch wiring (c = 3), version 4
        // the path mode and the lift.
        assert_eq!((r[100], r[101], r[102]), (3, PathMode::Joint.id(), 35));
        // Version 5 the touch's hold, repeat (hundredths of a second) and
        // cancel radius (counts).
        assert_eq!((r[103], r[104], r[105]), (25, 50, 90));
        // Version 6 the links (hundredths of a mm) and the home and park
        // poses (i16 hundredths of a degree).
        assert_eq!((&r[106..108], &r[108..110]), (&12_050u16.to_le_bytes()[..], &8_000u16.to_le_bytes()[..]));
        assert_eq!(
            (&r[110..112], &r[112..114], &r[114..116]),
            (&[0x28, 0x23][..], &[0x94, 0x11][..], &[0x44, 0xCB][..])
        );
        assert_eq!((&r[116..118], &r[120..122]), (&[0xFF, 0xFF][..], &(-32_767i16).to_le_bytes()[..]));
        // Version 7 the touch mode (1: hold), version 8 the plate ratio.
        assert_eq!(r[122], 1);
        assert_eq!(&r[123..125], &431u16.to_le_bytes());
        assert_eq!(&r[125..127], &crc16(&r[..125]).to_le_bytes());
        let mut line = c;
        (line.path, line.lift_centi) = (PathMode::Line, None);
        let l = line.encode(9);
        assert_eq!((l[101], l[102]), (1, 0));
        assert_eq!(Config::decode(&l).unwrap().config, line);
        let d = Config::decode(&r).unwrap();
        assert_eq!(d, Record { seq: 0x1234, config: c });
    }

    /// A version-1 record (90 bytes, CRC of 0..88 at 88, written before the
    /// acceleration limits) still loads, with the default limits; the
    /// slot's bytes past it are whatever the EEPROM held.
    #[test]
    fn version_1_records_migrate_with_default_accelerations() {
        let c = sample_config();
        for tail in [0xFFu8, 0x00, 0x5A] {
            let mut r = [tail; RECORD_LEN];
            r[..88].copy_from_slice(&c.encode(41)[..88]);
            r[2] = 1;
            let crc = crc16(&r[..88]);
            r[88..90].copy_from_slice(&crc.to_le_bytes());
            let d = Config::decode(&r).unwrap();
            let mut want = c;
            for (w, d) in want.joints.iter_mut().zip(JointCal::DEFAULTS.iter()) {
                w.max_accel_rad_s2 = d.max_accel_rad_s2;
            }
            // No wiring before version 3 (the firmware probes at boot), joint
            // moves and no lift before version 4.
            want.wiring = None;
            (want.path, want.lift_centi) = (PathMode::Joint, None);
            // The default hold, repeat and radius before version 5, the
            // default arm before version 6.
            want.press = PressSettings::DEFAULT;
            want.arm = ArmSettings::DEFAULT;
            want.hold_to_run = false;
            assert_eq!(d, Record { seq: 41, config: want }, "tail {tail:#x}");
            // A bad version-1 CRC is a CRC error, not a migration.
            let mut bad = r;
            bad[40] ^= 1;
            assert_eq!(Config::decode(&bad), Err(RecordError::Crc));
        }
        // Through load: one slot of each version, the newer sequence wins.
        let mut ee = SimEeprom::new();
        let mut v1 = [0xFFu8; RECORD_LEN];
        v1[..88].copy_from_slice(&c.encode(5)[..88]);
        v1[2] = 1;
        let crc = crc16(&v1[..88]);
        v1[88..90].copy_from_slice(&crc.to_le_bytes());
        ee.write(u32::from(SLOT_A_ADDR), &v1[..90]).unwrap();
        let l = load(&mut ee);
        assert_eq!((l.source, l.seq, l.warning), (Source::SlotA, 5, Some(Warning::CopyDamaged)));
        assert_eq!(l.config.joints[1].max_accel_rad_s2, JointCal::DEFAULTS[1].max_accel_rad_s2);
        assert_eq!(save(&mut ee, &l.config), Ok(6));
        let l = load(&mut ee);
        assert_eq!((l.seq, l.warning), (6, None));
    }

    /// A version-2 record (102 bytes, CRC of 0..100 at 100, written before
    /// the measured wiring) loads with every field but the wiring, which is
    /// none; the next save writes version 4 with the wiring the probe found.
    #[test]
    fn version_2_records_migrate_without_a_wiring() {
        let c = sample_config();
        for tail in [0xFFu8, 0x00, 0x02] {
            let mut r = [tail; RECORD_LEN];
            r[..100].copy_from_slice(&c.encode(77)[..100]);
            r[2] = 2;
            let crc = crc16(&r[..100]);
            r[100..102].copy_from_slice(&crc.to_le_bytes());
            let want = Config {
                wiring: None,
                path: PathMode::Joint,
                lift_centi: None,
                press: PressSettings::DEFAULT,
                arm: ArmSettings::DEFAULT,
                hold_to_run: false,
                ..c
            };
            assert_eq!(Config::decode(&r), Ok(Record { seq: 77, config: want }), "tail {tail:#x}");
            let mut bad = r;
            bad[60] ^= 1;
            assert_eq!(Config::decode(&bad), Err(RecordError::Crc));
        }
        let mut ee = SimEeprom::new();
        let mut v2 = [0u8; 102];
        v2[..100].copy_from_slice(&c.encode(9)[..100]);
        v2[2] = 2;
        let crc = crc16(&v2[..100]);
        v2[100..].copy_from_slice(&crc.to_le_bytes());
        ee.write(u32::from(SLOT_A_ADDR), &v2).unwrap();
        ee.write(u32::from(SLOT_B_ADDR), &v2).unwrap();
        let l = load(&mut ee);
        assert_eq!((l.source, l.seq, l.warning, l.config.wiring), (Source::SlotA, 9, None, None));
        let found = Config { wiring: Some(Wiring::A), ..l.config };
        assert_eq!(save(&mut ee, &found), Ok(10));
        let l = load(&mut ee);
        assert_eq!((l.seq, l.warning, l.config), (10, None, found));
        assert_eq!(record(&mut ee, SLOT_B_ADDR)[2], VERSION);
    }

    /// A version-3 record (103 bytes, CRC of 0..101 at 101, written before
    /// the path and lift settings) still loads, with its wiring, joint moves
    /// and no lift; the next save writes version 4.
    #[test]
    fn version_3_records_migrate_with_joint_moves_and_no_lift() {
        let c = sample_config();
        let v3 = |seq: u16, tail: u8| {
            let mut r = [tail; RECORD_LEN];
            r[..101].copy_from_slice(&c.encode(seq)[..101]);
            r[2] = 3;
            let crc = crc16(&r[..101]);
            r[101..103].copy_from_slice(&crc.to_le_bytes());
            r
        };
        let mut want = c;
        want.lift_centi = None;
        want.press = PressSettings::DEFAULT;
        want.arm = ArmSettings::DEFAULT;
        want.hold_to_run = false;
        for tail in [0xFFu8, 0x00, 0x5A] {
            assert_eq!(Config::decode(&v3(41, tail)), Ok(Record { seq: 41, config: want }), "tail {tail:#x}");
            let mut bad = v3(41, tail);
            bad[95] ^= 1;
            assert_eq!(Config::decode(&bad), Err(RecordError::Crc));
        }
        let mut ee = SimEeprom::new();
        ee.write(u32::from(SLOT_A_ADDR), &v3(5, 0xFF)[..103]).unwrap();
        let l = load(&mut ee);
        assert_eq!((l.source, l.seq, l.config), (Source::SlotA, 5, want));
        assert_eq!(save(&mut ee, &l.config), Ok(6));
        let l = load(&mut ee);
        assert_eq!((l.seq, l.warning), (6, None));
        assert_eq!(record(&mut ee, SLOT_A_ADDR)[2], VERSION);
    }

    /// A version-4 record (105 bytes, CRC of 0..103 at 103, written before
    /// the touch's hold, repeat and radius) loads with every field it has
    /// and the default hold, repeat and radius; the next save writes
    /// version 5.
    #[test]
    fn version_4_records_migrate_to_the_default_press_settings() {
        let c = sample_config();
        let v4 = |seq: u16, tail: u8| {
            let mut r = [tail; RECORD_LEN];
            r[..103].copy_from_slice(&c.encode(seq)[..103]);
            r[2] = 4;
            let crc = crc16(&r[..103]);
            r[103..105].copy_from_slice(&crc.to_le_bytes());
            r
        };
        let want = Config { press: PressSettings::DEFAULT, arm: ArmSettings::DEFAULT, hold_to_run: false, ..c };
        assert_eq!(PressSettings::DEFAULT, PressSettings { hold_cs: 10, repeat_cs: 30, radius: 240, plate: 0 });
        for tail in [0xFFu8, 0x00, 0x5A] {
            assert_eq!(Config::decode(&v4(41, tail)), Ok(Record { seq: 41, config: want }), "tail {tail:#x}");
            let mut bad = v4(41, tail);
            bad[102] ^= 1;
            assert_eq!(Config::decode(&bad), Err(RecordError::Crc));
        }
        let mut ee = SimEeprom::new();
        ee.write(u32::from(SLOT_A_ADDR), &v4(5, 0xFF)[..105]).unwrap();
        ee.write(u32::from(SLOT_B_ADDR), &v4(4, 0xFF)[..105]).unwrap();
        let l = load(&mut ee);
        assert_eq!((l.source, l.seq, l.warning, l.config), (Source::SlotA, 5, None, want));
        // The next save: the current version with the settings set since.
        assert_eq!(save(&mut ee, &c), Ok(6));
        let l = load(&mut ee);
        assert_eq!((l.seq, l.warning, l.config), (6, None, c));
        assert_eq!(record(&mut ee, SLOT_B_ADDR)[2], VERSION);
    }

    /// `c` as an older layout wrote it: the first `crc_at` bytes of today's
    /// record under `version`, their CRC at `crc_at`, `tail` after it.
    fn older_record(c: &Config, seq: u16, tail: u8, version: u8, crc_at: usize) -> [u8; RECORD_LEN] {
        let mut r = [tail; RECORD_LEN];
        r[..crc_at].copy_from_slice(&c.encode(seq)[..crc_at]);
        r[2] = version;
        let crc = crc16(&r[..crc_at]);
        r[crc_at..crc_at + 2].copy_from_slice(&crc.to_le_bytes());
        r
    }

    /// An older record (`old`, CRC at `crc_at`) decodes to `want` whatever
    /// follows it, a flipped byte before its CRC refuses it; both slots of
    /// it load as `want`, and the next save of `c` writes today's record.
    fn assert_migrates(
        c: &Config,
        want: Config,
        tails: [u8; 3],
        crc_at: usize,
        old: impl Fn(u16, u8) -> [u8; RECORD_LEN],
    ) -> SimEeprom {
        for tail in tails {
            assert_eq!(Config::decode(&old(41, tail)), Ok(Record { seq: 41, config: want }), "tail {tail:#x}");
            let mut bad = old(41, tail);
            bad[crc_at - 1] ^= 1;
            assert_eq!(Config::decode(&bad), Err(RecordError::Crc));
        }
        let mut ee = SimEeprom::new();
        ee.write(u32::from(SLOT_A_ADDR), &old(5, 0xFF)[..crc_at + 2]).unwrap();
        ee.write(u32::from(SLOT_B_ADDR), &old(4, 0xFF)[..crc_at + 2]).unwrap();
        let l = load(&mut ee);
        assert_eq!((l.source, l.seq, l.warning, l.config), (Source::SlotA, 5, None, want));
        assert_eq!(save(&mut ee, c), Ok(6));
        let l = load(&mut ee);
        assert_eq!((l.seq, l.warning, l.config), (6, None, *c));
        ee
    }

    /// Today's record of `c` with `edit` applied and its CRC redone.
    fn resealed(c: &Config, edit: impl FnOnce(&mut [u8; RECORD_LEN])) -> [u8; RECORD_LEN] {
        let mut r = c.encode(9);
        edit(&mut r);
        let crc = crc16(&r[..RECORD_LEN - 2]);
        r[RECORD_LEN - 2..].copy_from_slice(&crc.to_le_bytes());
        r
    }

    /// A version-5 record (108 bytes, CRC of 0..106 at 106, written before
    /// the arm's own geometry) loads with every field it has and the
    /// default arm (equal links, home and park at 90°, 90°, −90°); the next
    /// save writes version 6.
    #[test]
    fn version_5_records_migrate_to_the_default_arm() {
        let c = sample_config();
        let want =
            Config { arm: ArmSettings::DEFAULT, hold_to_run: false, press: PressSettings { plate: 0, ..c.press }, ..c };
        assert_eq!(
            ArmSettings::DEFAULT,
            ArmSettings { l2_cmm: 10_000, l3_cmm: 10_000, home: [9000, 9000, -9000], park: [9000, 9000, -9000] }
        );
        let mut ee =
            assert_migrates(&c, want, [0xFF, 0x00, 0x5A], 106, |seq, tail| older_record(&c, seq, tail, 5, 106));
        assert_eq!(record(&mut ee, SLOT_B_ADDR)[2], VERSION);
    }

    /// A version-6 record (124 bytes, CRC of 0..122 at 122, written before
    /// hold to run) loads with every field it has and `mode tap`; the next
    /// save writes version 7, whose mode byte at 122 is 0 or 1 (anything
    /// else refuses the record whole).
    #[test]
    fn version_6_records_migrate_to_tap_mode() {
        let c = sample_config();
        let want = Config { hold_to_run: false, press: PressSettings { plate: 0, ..c.press }, ..c };
        let mut ee =
            assert_migrates(&c, want, [0xFF, 0x00, 0x01], 122, |seq, tail| older_record(&c, seq, tail, 6, 122));
        let r = record(&mut ee, SLOT_B_ADDR);
        assert_eq!((r[2], r[122]), (VERSION, 1));
        // The mode byte: 0 tap, 1 hold, anything else invalid.
        assert_eq!(Config::decode(&resealed(&c, |r| r[122] = 2)), Err(RecordError::Invalid));
    }

    /// A version-7 record (125 bytes, CRC of 0..123 at 123, written before
    /// the panel's plate ratio) loads with every field it has and the ratio
    /// not measured (0: the ratio's second-contact check off until a touch
    /// calibration); the next save writes version 8, whose ratio at 123 is
    /// 0 or 64..=1024 (anything else refuses the record whole).
    #[test]
    fn version_7_records_migrate_without_a_plate_ratio() {
        let c = sample_config();
        let want = Config { press: PressSettings { plate: 0, ..c.press }, ..c };
        let mut ee =
            assert_migrates(&c, want, [0xFF, 0x00, 0x01], 123, |seq, tail| older_record(&c, seq, tail, 7, 123));
        let r = record(&mut ee, SLOT_B_ADDR);
        assert_eq!((r[2], &r[123..125]), (VERSION, &431u16.to_le_bytes()[..]));
        assert_eq!(VERSION, 8);
        // The ratio: 0, or 0.25..=4.00 (64..=1024).
        for (plate, ok) in [(0u16, true), (1, false), (63, false), (64, true), (1024, true), (1025, false)] {
            let r = resealed(&c, |r| r[123..125].copy_from_slice(&plate.to_le_bytes()));
            assert_eq!(Config::decode(&r).is_ok(), ok, "plate {plate}");
        }
    }

    /// The arm's links: each 10..=650 mm, the longer at most 4x the shorter
    /// (exactly 4x accepted); a record holding other links is refused
    /// whole, as any invalid field is.
    #[test]
    fn arm_links_are_ranged_and_at_most_four_times_apart() {
        let ok = |l2_cmm: u16, l3_cmm: u16| ArmSettings { l2_cmm, l3_cmm, ..ArmSettings::DEFAULT }.is_valid();
        assert!(ok(1000, 4000) && ok(4000, 1000) && ok(65_000, 16_250) && ok(1000, 1000) && ok(65_000, 65_000));
        assert!(!ok(1000, 4001) && !ok(4001, 1000) && !ok(999, 999) && !ok(65_001, 65_000) && !ok(0, 0));
        let mut c = sample_config();
        c.arm.l3_cmm = 3_012; // 120.50 / 30.12 > 4
        assert_eq!(c.validate(), Err(ConfigError::Arm));
        let mut r = sample_config().encode(3);
        r[108..110].copy_from_slice(&3_012u16.to_le_bytes());
        let crc = crc16(&r[..125]);
        r[125..127].copy_from_slice(&crc.to_le_bytes());
        assert_eq!(Config::decode(&r), Err(RecordError::Invalid));
        // `cal set arm` goes through the same rule.
        let mut c = Config::DEFAULT;
        let set = CalSet::Arm { link: ArmLink::L2, cmm: 40_001 };
        assert_eq!(c.apply(&set), Err(ConfigError::Arm));
        assert_eq!(c, Config::DEFAULT);
        assert_eq!(c.apply(&CalSet::Arm { link: ArmLink::L2, cmm: 40_000 }), Ok(()));
        assert_eq!((c.arm.l2_cmm, c.arm.l3_cmm), (40_000, 10_000));
    }

    /// The poses' record (`config::poses`): explicit little-endian layout,
    /// the configuration's CRC, and every value check.
    #[test]
    fn pose_record_layout_and_rejections() {
        use touch_arm::config::poses::{Pose, Poses, POSE_RECORD_LEN, POSE_VERSION};
        let mut p = Poses::EMPTY;
        let pose = Pose { joints: [9000, -1, -36_000], grip: Some(4500) };
        let far = Pose { joints: [36_001, 0, 0], grip: None };
        let far_grip = Pose { joints: [0; 3], grip: Some(-36_001) };
        assert!(p.set(2, Some(pose)));
        let zero = Pose { joints: [0; 3], grip: None };
        assert!(!p.set(0, Some(zero)) && !p.set(5, None) && !p.set(1, Some(far)) && !p.set(1, Some(far_grip)));
        assert_eq!((p.get(1), p.get(2), p.get(0), p.get(5)), (None, Some(pose), None, None));
        let r = p.encode(0x0102);
        assert_eq!(r.len(), POSE_RECORD_LEN);
        assert_eq!((&r[0..2], r[2], &r[3..5]), (&b"TP"[..], POSE_VERSION, &[0x02, 0x01][..]));
        // Slot 1 unused (flag and zeros), slot 2 at 5 + 17: flags 3 (used,
        // with a gripper angle), the joints, the gripper.
        assert_eq!(&r[5..22], &[0u8; 17]);
        assert_eq!(r[22], 3);
        assert_eq!(&r[23..27], &9000i32.to_le_bytes());
        assert_eq!(&r[27..31], &(-1i32).to_le_bytes());
        assert_eq!(&r[31..35], &(-36_000i32).to_le_bytes());
        assert_eq!(&r[35..39], &4500i32.to_le_bytes());
        assert_eq!(&r[73..75], &crc16(&r[..73]).to_le_bytes());
        assert_eq!(Poses::decode(&r), Ok((0x0102, p)));
        for i in 3..POSE_RECORD_LEN {
            let mut bad = r;
            bad[i] ^= 0x08;
            assert_eq!(Poses::decode(&bad), Err(RecordError::Crc), "byte {i}");
        }
        let mut v = r;
        v[2] = 3;
        assert_eq!(Poses::decode(&v), Err(RecordError::Version(3)));
        let reseal = |mut r: [u8; POSE_RECORD_LEN]| {
            let crc = crc16(&r[..73]);
            r[73..].copy_from_slice(&crc.to_le_bytes());
            r
        };
        // A flag of 2 (a gripper angle in an unused slot), an unused slot
        // with an angle, an angle past 360°.
        for (at, bytes) in [(5usize, vec![2u8]), (6, vec![1]), (23, 36_001i32.to_le_bytes().to_vec())] {
            let mut bad = r;
            bad[at..at + bytes.len()].copy_from_slice(&bytes);
            assert_eq!(Poses::decode(&reseal(bad)), Err(RecordError::Invalid), "at {at}");
        }
    }

    #[test]
    fn decode_rejections() {
        let good = sample_config().encode(7);
        let mut r = good;
        r[0] = 0xFF;
        assert_eq!(Config::decode(&r), Err(RecordError::NoMagic));
        assert_eq!(Config::decode(&[0xFF; RECORD_LEN]), Err(RecordError::NoMagic));
        let mut r = good;
        r[2] = 9;
        assert_eq!(Config::decode(&r), Err(RecordError::Version(9)));
        for i in 3..RECORD_LEN {
            let mut r = good;
            r[i] ^= 0x40;
            assert_eq!(Config::decode(&r), Err(RecordError::Crc), "byte {i}");
        }
        // CRC right but values invalid: unknown law, stray flag bits, NaN scale.
        let reseal = |mut r: [u8; RECORD_LEN]| {
            let crc = crc16(&r[..125]);
            r[125..].copy_from_slice(&crc.to_le_bytes());
            r
        };
        // Also: a touch mode of 2, an unknown wiring id, an unknown path mode, a lift over 0.5,
        // a lift with path line (sample_config lifts by 0.35), a hold below
        // 0.04 s or above 2 s, a repeat above 2 s, a radius below 20, an l2
        // of 0.18 mm (its high byte 0), an l3 of 653.44 mm (its high byte
        // 255).
        for (off, val) in [
            (122usize, 2u8),
            (107, 0),
            (109, 255),
            (87, 9),
            (86, 3),
            (85, 0x08),
            (100, 4),
            (101, 2),
            (102, 51),
            (101, 1),
            (103, 3),
            (103, 201),
            (104, 201),
            (105, 19),
        ] {
            let mut r = good;
            r[off] = val;
            assert_eq!(Config::decode(&reseal(r)), Err(RecordError::Invalid));
        }
        let mut r = good;
        r[9..13].copy_from_slice(&f32::NAN.to_le_bytes());
        assert_eq!(Config::decode(&reseal(r)), Err(RecordError::Invalid));
        // An acceleration limit that is not positive.
        let mut r = good;
        r[92..96].copy_from_slice(&0.0f32.to_le_bytes());
        assert_eq!(Config::decode(&reseal(r)), Err(RecordError::Invalid));
    }

    fn any_config() -> impl Strategy<Value = Config> {
        let joint = (
            1000.0f32..1500.0,
            prop_oneof![150.0f32..1500.0, -1500.0f32..-150.0],
            500u16..1500,
            1000u16..=2500,
            -3.0f32..0.0,
            0.5f32..3.0,
            0.5f32..20.0,
            0.5f32..1000.0,
        )
            .prop_map(|(o, k, lo, hi, a, b, v, acc)| JointCal {
                offset_us: o,
                us_per_rad: k,
                min_us: lo,
                max_us: hi.max(lo + 1),
                min_rad: a,
                max_rad: b,
                max_speed_rad_s: v,
                max_accel_rad_s2: acc,
            });
        let touch = (0u16..400, 600u16..=1023, 0u16..400, 600u16..=1023, any::<[bool; 3]>()).prop_map(
            |(x_min, x_max, y_min, y_max, f)| Calibration {
                x_min,
                x_max,
                y_min,
                y_max,
                swap_xy: f[0],
                invert_x: f[1],
                invert_y: f[2],
            },
        );
        let path_lift = prop_oneof![
            Just((PathMode::Line, None)),
            Just((PathMode::Joint, None)),
            (1u8..=50).prop_map(|h| (PathMode::Joint, Some(h))),
        ];
        let plate = prop_oneof![Just(0u16), 64u16..=1024];
        let press = (4u8..=200, 0u8..=200, 20u8..=255, plate)
            .prop_map(|(hold_cs, repeat_cs, radius, plate)| PressSettings { hold_cs, repeat_cs, radius, plate });
        // Links within their range (the filter drops pairs over 4x apart),
        // named poses anywhere an i16 reaches.
        let arm = (1000u16..=65000, 1000u16..=65000, any::<[i16; 3]>(), any::<[i16; 3]>())
            .prop_map(|(l2_cmm, l3_cmm, home, park)| ArmSettings { l2_cmm, l3_cmm, home, park });
        (prop::array::uniform3(joint), touch, 0u8..3, 0u8..6, (0u8..4, path_lift, press, arm, any::<bool>()))
            .prop_map(|(joints, touch, s, l, (w, (path, lift_centi), press, arm, hold_to_run))| Config {
                joints,
                touch,
                speed: SpeedPreset::from_id(s).unwrap(),
                law: LawKind::from_id(l).unwrap(),
                wiring: Wiring::from_id(w),
                path,
                lift_centi,
                press,
                arm,
                hold_to_run,
            })
            .prop_filter("valid", |c| c.validate().is_ok())
    }

    proptest! {
        #![proptest_config(cfg())]
        #[test]
        fn encode_decode_round_trip(c in any_config(), seq in any::<u16>()) {
            let r = c.encode(seq);
            let d = Config::decode(&r).unwrap();
            prop_assert_eq!(d.seq, seq);
            // Bit-exact, not just approximately equal.
            for (a, b) in d.config.joints.iter().zip(c.joints.iter()) {
                prop_assert_eq!(a.offset_us.to_bits(), b.offset_us.to_bits());
                prop_assert_eq!(a.us_per_rad.to_bits(), b.us_per_rad.to_bits());
                prop_assert_eq!(a.min_rad.to_bits(), b.min_rad.to_bits());
            }
            prop_assert_eq!(d.config, c);
            prop_assert_eq!(d.config.encode(seq), r);
        }
    }

    #[test]
    fn ids_and_names_round_trip() {
        for p in PathMode::ALL {
            assert_eq!(PathMode::from_id(p.id()), Some(p));
            assert_eq!(PathMode::from_name(p.name().as_str().as_bytes()), Some(p));
        }
        assert_eq!(PathMode::from_id(2), None);
        for l in LawKind::ALL {
            assert_eq!(LawKind::from_id(l.id()), Some(l));
            assert_eq!(LawKind::from_name(l.name().as_str().as_bytes()), Some(l));
        }
        for p in SpeedPreset::ALL {
            assert_eq!(SpeedPreset::from_id(p.id()), Some(p));
            assert_eq!(SpeedPreset::from_name(p.name().as_str().as_bytes()), Some(p));
        }
        // Stable ids: the papers' ζ-a-tₛ came last.
        assert_eq!(LawKind::ALL.map(|l| l.id()), [0, 5, 1, 2, 3, 4]);
        assert_eq!(LawKind::from_id(6), None);
        assert_eq!(LawKind::from_name(b"zat-paper"), Some(LawKind::ZatPaper));
        assert_eq!(SpeedPreset::from_id(3), None);
        assert_eq!(SpeedPreset::ALL.map(|p| p.percent()), [25, 50, 100]);
    }

    #[test]
    fn blank_eeprom_gives_defaults_and_missing() {
        let mut e = SimEeprom::new();
        let l = load(&mut e);
        assert_eq!(l.config, Config::DEFAULT);
        assert_eq!(l.source, Source::Defaults);
        assert_eq!(l.warning, Some(Warning::Missing));
    }

    #[test]
    fn save_then_load_and_sequence() {
        let mut e = SimEeprom::new();
        let c = sample_config();
        assert_eq!(save(&mut e, &c), Ok(1));
        let l = load(&mut e);
        assert_eq!((l.config, l.seq, l.warning), (c, 1, None));
        // Both copies hold the record.
        assert_eq!(record(&mut e, SLOT_A_ADDR), &c.encode(1)[..]);
        assert_eq!(record(&mut e, SLOT_B_ADDR), &c.encode(1)[..]);
        assert_eq!(save(&mut e, &Config::DEFAULT), Ok(2));
        assert_eq!(load(&mut e).config, Config::DEFAULT);
        // Nothing outside the two slots is touched.
        assert!(e.mem[RECORD_LEN..SLOT_B_ADDR as usize].iter().all(|&b| b == 0xFF));
        assert!(e.mem[SLOT_B_ADDR as usize + RECORD_LEN..].iter().all(|&b| b == 0xFF));
    }

    #[test]
    fn one_corrupt_copy_uses_the_other() {
        let c = sample_config();
        for slot in [SLOT_A_ADDR, SLOT_B_ADDR] {
            for i in 0..RECORD_LEN {
                let mut e = SimEeprom::new();
                save(&mut e, &c).unwrap();
                record(&mut e, slot)[i] ^= 0x10;
                let l = load(&mut e);
                assert_eq!(l.config, c, "slot {slot} byte {i}");
                assert_eq!(l.warning, Some(Warning::CopyDamaged));
                let other = if slot == SLOT_A_ADDR { Source::SlotB } else { Source::SlotA };
                assert_eq!(l.source, other);
                // The next save repairs both copies.
                save(&mut e, &c).unwrap();
                assert_eq!(load(&mut e).warning, None);
            }
        }
    }

    #[test]
    fn both_corrupt_gives_defaults_and_warning() {
        let c = sample_config();
        let mut e = SimEeprom::new();
        save(&mut e, &c).unwrap();
        record(&mut e, SLOT_A_ADDR)[40] ^= 1;
        record(&mut e, SLOT_B_ADDR)[7] ^= 0x80;
        let l = load(&mut e);
        assert_eq!((l.config, l.source, l.warning), (Config::DEFAULT, Source::Defaults, Some(Warning::Corrupt)));
        // One copy from another layout version, the other never written.
        let mut e = SimEeprom::new();
        let mut r = c.encode(3);
        r[2] = VERSION + 1;
        record(&mut e, SLOT_A_ADDR).copy_from_slice(&r);
        let l = load(&mut e);
        assert_eq!((l.config, l.warning), (Config::DEFAULT, Some(Warning::VersionMismatch)));
        // Version mismatch outranks corruption in the report.
        record(&mut e, SLOT_B_ADDR).copy_from_slice(&c.encode(3));
        record(&mut e, SLOT_B_ADDR)[50] ^= 4;
        assert_eq!(load(&mut e).warning, Some(Warning::VersionMismatch));
        // A storage that cannot be read reports corruption, not a panic.
        struct Dead;
        impl ReadStorage for Dead {
            type Error = StorageError;
            fn read(&mut self, _: u32, _: &mut [u8]) -> Result<(), StorageError> {
                Err(StorageError::Device)
            }
            fn capacity(&self) -> usize {
                4096
            }
        }
        impl Storage for Dead {
            fn write(&mut self, _: u32, _: &[u8]) -> Result<(), StorageError> {
                Err(StorageError::Device)
            }
        }
        let l = load(&mut Dead);
        assert_eq!((l.config, l.warning), (Config::DEFAULT, Some(Warning::Corrupt)));
        assert_eq!(save(&mut Dead, &c), Err(SaveError::Storage(StorageError::Device)));
    }

    #[test]
    fn newest_copy_wins_with_wraparound() {
        let a = Config::DEFAULT;
        let b = sample_config();
        let mut e = SimEeprom::new();
        record(&mut e, SLOT_A_ADDR).copy_from_slice(&a.encode(0xFFFF));
        record(&mut e, SLOT_B_ADDR).copy_from_slice(&b.encode(0x0000));
        let l = load(&mut e);
        assert_eq!((l.config, l.source, l.seq), (b, Source::SlotB, 0));
        record(&mut e, SLOT_B_ADDR).copy_from_slice(&b.encode(0xFFFE));
        assert_eq!(load(&mut e).config, a);
        // Saving past the wrap keeps counting.
        record(&mut e, SLOT_B_ADDR).copy_from_slice(&b.encode(0xFFFF));
        assert_eq!(save(&mut e, &b), Ok(0));
        assert_eq!(load(&mut e).seq, 0);
        assert!(seq_newer(1, 0) && seq_newer(0, 0xFFFF) && !seq_newer(5, 5) && !seq_newer(0xFFFF, 0));
    }

    #[test]
    fn invalid_config_is_not_saved() {
        let mut e = SimEeprom::new();
        let mut c = Config::DEFAULT;
        c.touch.x_min = 2000;
        c.touch.x_max = 3000;
        assert_eq!(save(&mut e, &c), Err(SaveError::Invalid(ConfigError::Touch(TouchCalError::OutOfRange))));
        assert!(e.mem.iter().all(|&b| b == 0xFF));
    }

    #[test]
    fn failed_verify_stops_before_second_copy() {
        /// Accepts writes but stores an inverted byte: verify must catch it.
        struct Flaky(Vec<u8>);
        impl ReadStorage for Flaky {
            type Error = StorageError;
            fn read(&mut self, offset: u32, buf: &mut [u8]) -> Result<(), StorageError> {
                let addr = offset as usize;
                buf.copy_from_slice(&self.0[addr..addr + buf.len()]);
                Ok(())
            }
            fn capacity(&self) -> usize {
                self.0.len()
            }
        }
        impl Storage for Flaky {
            fn write(&mut self, offset: u32, data: &[u8]) -> Result<(), StorageError> {
                let addr = offset as usize;
                self.0[addr..addr + data.len()].copy_from_slice(data);
                self.0[addr + 10] ^= 0xFF;
                Ok(())
            }
        }
        let mut f = Flaky(vec![0xFF; 4096]);
        assert_eq!(save(&mut f, &Config::DEFAULT), Err(SaveError::Verify));
        assert!(f.0[SLOT_B_ADDR as usize..].iter().all(|&b| b == 0xFF));
    }

    /// Power lost after `cut` bytes of a save; the byte at the cut is torn.
    fn interrupted_save(e: &mut SimEeprom, c: &Config, cut: usize, torn: u8) {
        e.power_loss_after(cut);
        e.torn_value = torn;
        let _ = save(e, c);
        e.restore_power();
    }

    proptest! {
        #![proptest_config(cfg())]
        /// A chain of saves, each possibly cut anywhere: after each, the loaded
        /// config is either the one before or the one being saved.
        #[test]
        fn repeated_power_loss(steps in prop::collection::vec((any_config(), prop::option::of(0usize..2 * RECORD_LEN), any::<u8>()), 1..8)) {
            let mut e = SimEeprom::new();
            let mut current = load(&mut e).config;
            for (c, cut, torn) in steps {
                match cut {
                    Some(k) => interrupted_save(&mut e, &c, k, torn),
                    None => { save(&mut e, &c).unwrap(); }
                }
                let l = load(&mut e);
                prop_assert!(l.config == current || l.config == c);
                if cut.is_none() {
                    prop_assert_eq!(l.config, c);
                }
                current = l.config;
            }
        }
    }

    #[test]
    fn cal_set_applies_validated_changes() {
        let mut c = Config::DEFAULT;
        let set = |joint, field, value| CalSet::Joint { joint, field, value };
        c.apply(&set(Joint::Base, JointField::Scale, 1000)).unwrap(); // 10.00 µs/deg
        assert!((c.joints[0].us_per_rad - 572.957_8).abs() < 1e-3);
        c.apply(&set(Joint::Shoulder, JointField::Offset, 61_050)).unwrap();
        assert_eq!(c.joints[1].offset_us, 610.5);
        c.apply(&set(Joint::Elbow, JointField::MinUs, 650)).unwrap();
        assert_eq!(c.joints[2].min_us, 650);
        c.apply(&set(Joint::Elbow, JointField::MinDeg, -9000)).unwrap();
        assert!((c.joints[2].min_rad as f64 + std::f64::consts::FRAC_PI_2).abs() < 1e-6);
        c.apply(&set(Joint::Base, JointField::MaxSpeed, 9000)).unwrap();
        assert!((c.joints[0].max_speed_rad_s as f64 - std::f64::consts::FRAC_PI_2).abs() < 1e-6);
        // Reading back in the same units.
        assert_eq!(c.joint_field(Joint::Base, JointField::Scale), 1000);
        assert_eq!(c.joint_field(Joint::Shoulder, JointField::Offset), 61_050);
        assert_eq!(c.joint_field(Joint::Elbow, JointField::MinDeg), -9000);
        assert_eq!(c.joint_field(Joint::Elbow, JointField::MaxDeg), 0);
        assert_eq!(c.joint_field(Joint::Base, JointField::MaxDeg), 18_000);
        assert_eq!(c.joint_field(Joint::Base, JointField::MaxSpeed), 9000);
        assert_eq!(c.joint_field(Joint::Elbow, JointField::MinUs), 650);
        // An invalid change is refused and leaves everything as it was.
        let before = c;
        assert_eq!(
            c.apply(&set(Joint::Base, JointField::MinUs, 2400)),
            Err(ConfigError::Joint(Joint::Base, JointCalError::PulseLimits))
        );
        assert_eq!(
            c.apply(&set(Joint::Elbow, JointField::Scale, 0)),
            Err(ConfigError::Joint(Joint::Elbow, JointCalError::Scale))
        );
        assert_eq!(
            c.apply(&CalSet::Touch { field: TouchField::XMax, value: 150 }),
            Err(ConfigError::Touch(TouchCalError::Span))
        );
        assert_eq!(c, before);
        c.apply(&CalSet::Touch { field: TouchField::InvertY, value: 1 }).unwrap();
        c.apply(&CalSet::Touch { field: TouchField::XMin, value: 50 }).unwrap();
        assert!(c.touch.invert_y && c.touch.x_min == 50 && !c.touch.swap_xy);
    }

    #[test]
    fn touch_cal_validation() {
        let d = Calibration::DEFAULT;
        assert_eq!(validate_touch(&d), Ok(()));
        assert_eq!(validate_touch(&Calibration { y_max: 1024, ..d }), Err(TouchCalError::OutOfRange));
        assert_eq!(validate_touch(&Calibration { x_min: 1024, x_max: 1023, ..d }), Err(TouchCalError::OutOfRange));
        assert_eq!(validate_touch(&Calibration { x_min: 932, ..d }), Err(TouchCalError::Order));
        assert_eq!(validate_touch(&Calibration { y_min: 900, ..d }), Err(TouchCalError::Order));
        assert_eq!(validate_touch(&Calibration { y_min: 800, ..d }), Err(TouchCalError::Span));
        assert_eq!(validate_touch(&Calibration { x_min: 0, x_max: 1023, ..d }), Ok(()));
    }
}

mod command {
    use super::*;
    use touch_arm::config::lcd::{LcdChoice, LcdSet};
    use touch_arm::config::settings::{CalSet, JointField, TouchField};
    use touch_arm::config::settings::{PathMode, SpeedPreset};
    use touch_arm::math::units::centideg_to_rad;
    use touch_arm::motion::plan::LawKind as Law;
    use touch_arm::protocol::command::*;
    use touch_arm::servo::map::Joint;

    #[test]
    fn every_command_parses() {
        use Command as C;
        let j = |joint, field, value| C::CalSet(CalSet::Joint { joint, field, value });
        let t = |field, value| C::CalSet(CalSet::Touch { field, value });
        let table: &[(&str, Command)] = &[
            ("move 527 512", C::Move { x: 527, y: 512 }),
            ("move 0 1023", C::Move { x: 0, y: 1023 }),
            ("move +5 007", C::Move { x: 5, y: 7 }),
            ("goto 90 45.5 -120.25", C::Goto { centideg: [9000, 4550, -12025] }),
            ("goto -360 360.00 0", C::Goto { centideg: [-36000, 36000, 0] }),
            ("goto 0.1 -0.05 +1", C::Goto { centideg: [10, -5, 100] }),
            ("stop", C::Stop),
            ("resume", C::Resume),
            ("status", C::Status),
            ("law zat", C::Law(Law::Zat)),
            ("law quintic", C::Law(Law::Quintic)),
            ("law cubic", C::Law(Law::Cubic)),
            ("law trapezoid", C::Law(Law::Trapezoid)),
            ("law linear", C::Law(Law::Linear)),
            ("speed slow", C::Speed(SpeedPreset::Slow)),
            ("speed normal", C::Speed(SpeedPreset::Normal)),
            ("speed fast", C::Speed(SpeedPreset::Fast)),
            ("cal show", C::CalShow),
            ("cal save", C::CalSave),
            ("cal reset", C::CalReset),
            ("cal set base offset 600", j(Joint::Base, JointField::Offset, 60_000)),
            ("cal set shoulder scale -10.5", j(Joint::Shoulder, JointField::Scale, -1050)),
            ("cal set elbow min_us 650", j(Joint::Elbow, JointField::MinUs, 650)),
            ("cal set elbow max_us 2500", j(Joint::Elbow, JointField::MaxUs, 2500)),
            ("cal set base min_deg -5.25", j(Joint::Base, JointField::MinDeg, -525)),
            ("cal set base max_deg 185", j(Joint::Base, JointField::MaxDeg, 18_500)),
            ("cal set shoulder max_speed 120.5", j(Joint::Shoulder, JointField::MaxSpeed, 12_050)),
            ("cal set touch x_min 123", t(TouchField::XMin, 123)),
            ("cal set touch x_max 932", t(TouchField::XMax, 932)),
            ("cal set touch y_min 128", t(TouchField::YMin, 128)),
            ("cal set touch y_max 897", t(TouchField::YMax, 897)),
            ("cal set touch swap 1", t(TouchField::Swap, 1)),
            ("cal set touch invert_x 0", t(TouchField::InvertX, 0)),
            ("cal set touch invert_y 1", t(TouchField::InvertY, 1)),
            ("log on", C::Log(LogMode::On)),
            ("log off", C::Log(LogMode::Off)),
            ("log plot", C::Log(LogMode::Plot)),
            ("help", C::Help),
            ("version", C::Version),
            // Keywords in any case (issue #21 §2): caps lock, a script's habits.
            ("STOP", C::Stop),
            ("Goto 1 2 3", C::Goto { centideg: [100, 200, 300] }),
            ("MOVE 500 500", C::Move { x: 500, y: 500 }),
            ("LAW Zat-Paper", C::Law(Law::ZatPaper)),
            ("Speed FAST", C::Speed(SpeedPreset::Fast)),
            ("LOG PLOT", C::Log(LogMode::Plot)),
            ("Path LINE", C::Path(PathMode::Line)),
            ("lift OFF", C::Lift(None)),
            ("CAL SET Base Offset 600", j(Joint::Base, JointField::Offset, 60_000)),
            ("cal set TOUCH X_MIN 123", t(TouchField::XMin, 123)),
            ("Cal Reset Grip", C::CalResetGrip),
            ("POSE GO 2", C::Pose(PoseCmd::Go(2))),
            ("pose LIST", C::Pose(PoseCmd::List)),
            ("GRIP Close", C::Grip(GripCmd::Close)),
            ("HeLp", C::Help),
            ("VERSION", C::Version),
            ("grip open", C::Grip(GripCmd::Open)),
            ("grip close", C::Grip(GripCmd::Close)),
            ("grip 45.5", C::Grip(GripCmd::Centideg(4550))),
            ("grip -360", C::Grip(GripCmd::Centideg(-36_000))),
            ("cal reset grip", C::CalResetGrip),
            // The assistive switch (issue #20 §4), the glass as one too.
            ("switch on", C::Access(AccessCmd::Switch(touch_arm::config::access::SwitchUse::On))),
            ("switch off", C::Access(AccessCmd::Switch(touch_arm::config::access::SwitchUse::Off))),
            ("SWITCH Glass", C::Access(AccessCmd::Switch(touch_arm::config::access::SwitchUse::Glass))),
            ("switch sweep 2", C::Access(AccessCmd::Sweep(20))),
            ("switch sweep 12.34", C::Access(AccessCmd::Sweep(123))),
            // The display overrides (issue #21 §3).
            ("cal set lcd auto", C::CalLcd(LcdSet::Controller(LcdChoice::Auto))),
            ("cal set lcd ili9341", C::CalLcd(LcdSet::Controller(LcdChoice::Ili9341))),
            ("cal set lcd st7789", C::CalLcd(LcdSet::Controller(LcdChoice::St7789))),
            ("cal set lcd ili9486", C::CalLcd(LcdSet::Controller(LcdChoice::Ili9486))),
            ("cal set lcd ili9325", C::CalLcd(LcdSet::Controller(LcdChoice::Ili9325))),
            ("CAL SET LCD ST7796", C::CalLcd(LcdSet::Controller(LcdChoice::St7796))),
            ("cal set lcd invert on", C::CalLcd(LcdSet::Invert(true))),
            ("cal set lcd Invert OFF", C::CalLcd(LcdSet::Invert(false))),
            ("cal set lcd rotate 180", C::CalLcd(LcdSet::Rotate180(true))),
            ("cal set lcd rotate 0", C::CalLcd(LcdSet::Rotate180(false))),
            ("cal set grip max_deg 60", C::CalSet(CalSet::Grip { field: JointField::MaxDeg, value: 6000 })),
            ("cal set grip min_us 700", C::CalSet(CalSet::Grip { field: JointField::MinUs, value: 700 })),
            ("path line", C::Path(PathMode::Line)),
            ("path joint", C::Path(PathMode::Joint)),
            ("circle 0.25", C::Circle { r_centi: 25 }),
            ("lift 0.2", C::Lift(Some(20))),
            ("lift 0.50", C::Lift(Some(50))),
            ("lift off", C::Lift(None)),
            ("circle 0.01", C::Circle { r_centi: 1 }),
            ("circle 0.5", C::Circle { r_centi: 50 }),
            // Lenient whitespace.
            ("  move\t12    34  ", C::Move { x: 12, y: 34 }),
            ("status\r\n", C::Status),
            ("\tcal  set\ttouch   swap 0 ", t(TouchField::Swap, 0)),
        ];
        for (line, want) in table {
            assert_eq!(parse(line.as_bytes()), Ok(*want), "{line:?}");
        }
        // Every name the enums know is accepted by the parser.
        for f in JointField::ALL {
            let v = if f.is_centi() { "1" } else { "600" };
            let line = format!("cal set base {} {v}", f.name());
            assert!(parse(line.as_bytes()).is_ok(), "{line}");
        }
        for f in TouchField::ALL {
            let v = if f == TouchField::Radius { "20" } else { "1" };
            let line = format!("cal set touch {} {v}", f.name());
            assert!(parse(line.as_bytes()).is_ok(), "{line}");
        }
        // The touch's press settings: seconds with two decimals, counts.
        for (line, want) in [
            ("cal set touch hold 0.04", t(TouchField::Hold, 4)),
            ("cal set touch hold 2", t(TouchField::Hold, 200)),
            ("cal set touch repeat 0", t(TouchField::Repeat, 0)),
            ("cal set touch repeat 0.3", t(TouchField::Repeat, 30)),
            ("cal set touch radius 255", t(TouchField::Radius, 255)),
        ] {
            assert_eq!(parse(line.as_bytes()), Ok(want), "{line:?}");
        }
        for line in [
            "cal set touch hold 0.03",
            "cal set touch hold 2.01",
            "cal set touch repeat 2.5",
            "cal set touch radius 19",
            "cal set touch radius 256",
        ] {
            assert_eq!(parse(line.as_bytes()), Err(CmdError::OutOfRange), "{line:?}");
        }
        assert_eq!(parse(b"cal set touch hold 0.125"), Err(CmdError::BadNumber));
    }

    #[test]
    fn malformed_lines() {
        use CmdError as E;
        let table: &[(&[u8], CmdError)] = &[
            (b"", E::Empty),
            (b"   \t ", E::Empty),
            (b"\r\n", E::Empty),
            (b"jump", E::UnknownCommand),
            (b"MOVE 1 2 3", E::ExtraArgument),
            (b"STOPP", E::UnknownCommand),
            (b"help me", E::ExtraArgument),
            (b"version 2", E::ExtraArgument),
            (b"log plotter", E::BadArgument),
            (b"cal set lcd", E::MissingArgument),
            (b"cal set lcd ssd1289", E::BadArgument),
            (b"cal set lcd rotate 90", E::BadArgument),
            (b"cal set lcd rotate", E::MissingArgument),
            (b"cal set lcd invert yes", E::BadArgument),
            (b"cal set lcd invert on off", E::ExtraArgument),
            (b"cal set lcd auto now", E::ExtraArgument),
            // `!` is the port's one-byte STOP, never a command word.
            (b"!", E::UnknownCommand),
            (b"movex 1 2", E::UnknownCommand),
            (b"move", E::MissingArgument),
            (b"move 1", E::MissingArgument),
            (b"move 1 2 3", E::ExtraArgument),
            (b"stop now", E::ExtraArgument),
            (b"status 1", E::ExtraArgument),
            (b"move 1024 5", E::OutOfRange),
            (b"move 5 -1", E::OutOfRange),
            (b"move 99999999999999 1", E::OutOfRange),
            (b"move 1.5 2", E::BadNumber),
            (b"move 0x10 2", E::BadNumber),
            (b"move - 2", E::BadNumber),
            (b"move 1-2 3", E::BadNumber),
            (b"move 1 2abc", E::BadNumber),
            (b"goto 1 2", E::MissingArgument),
            (b"goto 1 2 3 4", E::ExtraArgument),
            (b"goto 360.01 0 0", E::OutOfRange),
            (b"goto 0 -400 0", E::OutOfRange),
            (b"goto 1.234 0 0", E::BadNumber),
            (b"goto .5 0 0", E::BadNumber),
            (b"goto 1. 0 0", E::BadNumber),
            (b"goto 1e2 0 0", E::BadNumber),
            (b"goto 1,5 0 0", E::BadNumber),
            (b"goto 1..5 0 0", E::BadNumber),
            (b"goto -+1 0 0", E::BadNumber),
            (b"goto nan 0 0", E::BadNumber),
            (b"goto inf 0 0", E::BadNumber),
            (b"law", E::MissingArgument),
            (b"law fast", E::BadArgument),
            (b"law Zats", E::BadArgument),
            (b"law zat quintic", E::ExtraArgument),
            (b"speed warp", E::BadArgument),
            (b"log maybe", E::BadArgument),
            (b"log", E::MissingArgument),
            (b"path", E::MissingArgument),
            (b"path curve", E::BadArgument),
            (b"path line joint", E::ExtraArgument),
            (b"circle", E::MissingArgument),
            (b"lift", E::MissingArgument),
            (b"lift on", E::BadNumber),
            (b"lift 0", E::OutOfRange),
            (b"lift 0.51", E::OutOfRange),
            (b"lift off 1", E::ExtraArgument),
            (b"circle 0", E::OutOfRange),
            (b"circle 0.51", E::OutOfRange),
            (b"circle -0.2", E::OutOfRange),
            (b"circle 0.125", E::BadNumber),
            (b"circle 0.2 0.3", E::ExtraArgument),
            (b"cal", E::MissingArgument),
            (b"cal load", E::BadArgument),
            (b"cal show all", E::ExtraArgument),
            (b"cal set", E::MissingArgument),
            (b"cal set wrist offset 1", E::BadArgument),
            (b"cal set base", E::MissingArgument),
            (b"cal set base gain 1", E::BadArgument),
            (b"cal set base offset", E::MissingArgument),
            (b"cal set base offset 1 2", E::ExtraArgument),
            (b"cal set base min_us 1500.5", E::BadNumber),
            (b"cal set base min_us 499", E::OutOfRange),
            (b"cal set base max_us 2501", E::OutOfRange),
            (b"grip", E::MissingArgument),
            (b"grip shut", E::BadNumber),
            (b"grip open now", E::ExtraArgument),
            (b"grip 360.01", E::OutOfRange),
            (b"cal reset base", E::ExtraArgument),
            (b"cal set grip max_us 2501", E::OutOfRange),
            (b"cal set base scale 100.01", E::OutOfRange),
            (b"cal set base max_speed -1", E::OutOfRange),
            (b"cal set touch x_min 1024", E::OutOfRange),
            (b"cal set touch swap 2", E::OutOfRange),
            (b"cal set touch swap yes", E::BadNumber),
            (b"cal set touch tilt 1", E::BadArgument),
            // Non-ASCII and control bytes anywhere.
            ("move 1 2\u{b2}".as_bytes(), E::BadCharacter),
            ("l\u{e4}w zat".as_bytes(), E::BadCharacter),
            (b"stop\x00", E::BadCharacter),
            (b"st\x1bop", E::BadCharacter),
            (b"\xff", E::BadCharacter),
            (&[b'a'; 100], E::TooLong),
        ];
        for (line, want) in table {
            assert_eq!(parse(line), Err(*want), "{:?}", String::from_utf8_lossy(line));
        }
        // Every error has a short reason.
        for (_, e) in table {
            assert!(!e.reason().is_empty() && e.reason().len() <= 20);
        }
    }

    #[test]
    fn numbers() {
        let c = |s: &str| parse_centi(s.as_bytes(), i32::MIN, i32::MAX);
        assert_eq!(c("12"), Ok(1200));
        assert_eq!(c("-0.5"), Ok(-50));
        assert_eq!(c("90.25"), Ok(9025));
        assert_eq!(c("+1.2"), Ok(120));
        assert_eq!(c("-0"), Ok(0));
        assert_eq!(c("21474836.47"), Ok(i32::MAX));
        assert_eq!(c("21474836.48"), Err(CmdError::OutOfRange));
        assert_eq!(c("-21474836.47"), Ok(-i32::MAX));
        for bad in ["", "-", "+", ".", ".5", "1.", "1.234", "1e3", " 1", "1 ", "--1", "1.-5"] {
            assert_eq!(c(bad), Err(CmdError::BadNumber), "{bad:?}");
        }
        let i = |s: &str| parse_int(s.as_bytes(), -1000, 1000);
        assert_eq!(i("-1000"), Ok(-1000));
        assert_eq!(i("1001"), Err(CmdError::OutOfRange));
        assert_eq!(i("2147483648"), Err(CmdError::OutOfRange));
        assert_eq!(i("1.0"), Err(CmdError::BadNumber));
    }

    proptest! {
        #![proptest_config(cfg())]
        #[test]
        fn centi_round_trip(v in -i32::MAX..=i32::MAX, decimals in 0usize..3) {
            // Printed with 0, 1 or 2 decimals (when exact), parsed back.
            let (sign, mag) = if v < 0 { ("-", v.unsigned_abs()) } else { ("", v as u32) };
            let s = match decimals {
                0 => format!("{sign}{}.{:02}", mag / 100, mag % 100),
                1 if mag % 10 == 0 => format!("{sign}{}.{}", mag / 100, (mag % 100) / 10),
                _ if mag % 100 == 0 => format!("{sign}{}", mag / 100),
                _ => format!("{sign}{}.{:02}", mag / 100, mag % 100),
            };
            prop_assert_eq!(parse_centi(s.as_bytes(), i32::MIN, i32::MAX), Ok(v), "{}", s);
        }

        #[test]
        fn move_accepts_exactly_the_adc_range(x in -5000i32..5000, y in 0i32..1024) {
            let r = parse(format!("move {x} {y}").as_bytes());
            if (0..=1023).contains(&x) {
                prop_assert_eq!(r, Ok(Command::Move { x: x as u16, y: y as u16 }));
            } else {
                prop_assert_eq!(r, Err(CmdError::OutOfRange));
            }
        }

        #[test]
        fn parse_never_panics(line in prop::collection::vec(any::<u8>(), 0..80)) {
            let _ = parse(&line);
        }
    }

    #[test]
    fn centideg_conversion() {
        let r = |cd| centideg_to_rad::<f64>(cd);
        assert!((r(18_000) - std::f64::consts::PI).abs() < 1e-12);
        assert!((r(-9000) + std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        assert_eq!(r(0), 0.0);
        assert!((r(i32::MAX) - i32::MAX as f64 * std::f64::consts::PI / 18_000.0).abs() < 1e-3);
        assert!((r(i32::MIN) + 2_147_483_648.0 * std::f64::consts::PI / 18_000.0).abs() < 1e-3);
        assert!((centideg_to_rad::<f32>(4550) - 0.794_124_6).abs() < 1e-6);
    }

    /// Collects the results of feeding `bytes`.
    fn feed<const N: usize>(lb: &mut LineBuffer<N>, bytes: &[u8]) -> Vec<Result<Vec<u8>, CmdError>> {
        let mut out = vec![];
        for &b in bytes {
            if let Some(r) = lb.push(b) {
                out.push(r.map(|l| l.to_vec()));
            }
        }
        out
    }

    #[test]
    fn line_buffer_terminators() {
        let mut lb = SerialLine::new();
        assert_eq!(feed(&mut lb, b"stop\n"), vec![Ok(b"stop".to_vec())]);
        assert_eq!(feed(&mut lb, b"move 1 2\r\n"), vec![Ok(b"move 1 2".to_vec())]);
        assert_eq!(feed(&mut lb, b"status\rlog on\r"), vec![Ok(b"status".to_vec()), Ok(b"log on".to_vec())]);
        // The previous feed ended in \r, so this \n completes a \r\n and adds
        // nothing; then two blank lines, reported as empty (the app may ignore them).
        assert_eq!(feed(&mut lb, b"\n\r\n\n"), vec![Ok(vec![]), Ok(vec![])]);
        // Partial input produces nothing until the terminator.
        assert_eq!(feed(&mut lb, b"res"), vec![]);
        assert_eq!(feed(&mut lb, b"ume\n"), vec![Ok(b"resume".to_vec())]);
        // Backspace and DEL edit the line.
        assert_eq!(feed(&mut lb, b"stx\x08op\n"), vec![Ok(b"stop".to_vec())]);
        assert_eq!(feed(&mut lb, b"\x7f\x7fab\x7fc\n"), vec![Ok(b"ac".to_vec())]);
    }

    #[test]
    fn line_buffer_overflow_recovers() {
        let mut lb = SerialLine::new();
        // Exactly LINE_LEN bytes fit.
        let full = vec![b'x'; LINE_LEN];
        let mut bytes = full.clone();
        bytes.push(b'\n');
        assert_eq!(feed(&mut lb, &bytes), vec![Ok(full)]);
        // One more is too long, reported once, and the next line is fine.
        let mut bytes = vec![b'y'; LINE_LEN + 1];
        bytes.extend_from_slice(b"\r\n");
        bytes.extend_from_slice(b"status\n");
        assert_eq!(feed(&mut lb, &bytes), vec![Err(CmdError::TooLong), Ok(b"status".to_vec())]);
        // A very long flood, including backspaces while discarding.
        let mut bytes = vec![b'z'; 1000];
        bytes.extend_from_slice(&[0x08; 5]);
        bytes.extend_from_slice(b"\nlog off\n");
        assert_eq!(feed(&mut lb, &bytes), vec![Err(CmdError::TooLong), Ok(b"log off".to_vec())]);
        // The recovered line parses.
        let mut lb = SerialLine::new();
        let mut got = None;
        for &b in b"goto 10 20 30\n" {
            if let Some(r) = lb.push(b) {
                got = Some(r.and_then(parse));
            }
        }
        assert_eq!(got, Some(Ok(Command::Goto { centideg: [1000, 2000, 3000] })));
        lb.push(b'a');
        lb.clear();
        assert_eq!(feed(&mut lb, b"stop\n"), vec![Ok(b"stop".to_vec())]);
    }

    #[test]
    fn line_buffer_expires_partial_lines() {
        let mut lb = SerialLine::new();
        // Nothing waiting: nothing owed.
        assert!(!lb.expire());
        // A partial line is owed its `err line timeout`, once.
        feed(&mut lb, b"resume 12");
        assert!(lb.is_partial());
        assert!(lb.expire());
        assert!(!lb.is_partial() && !lb.expire());
        // An over-long partial line too (it was never answered).
        feed(&mut lb, &[b'x'; LINE_LEN + 5]);
        assert!(lb.expire());
        // The rest of a line a receive loss cut into is not: the loss was answered.
        lb.after_loss(&touch_arm::seam::RxLoss { lines: 1, rest_damaged: true, after_cr: false });
        feed(&mut lb, b"ve 1 2");
        assert!(lb.is_partial());
        assert!(!lb.expire());
        // After expiry the next line is read whole.
        assert_eq!(feed(&mut lb, b"stop\n"), vec![Ok(b"stop".to_vec())]);
        assert_eq!(CmdError::LineTimeout.reason(), "line timeout (no line ending?)");
    }

    /// `help` lists `Verb::ALL`: every word of it is a command the parser
    /// knows (by itself, or missing only its arguments), in any case.
    #[test]
    fn every_verb_parses() {
        assert_eq!(Verb::all().collect::<Vec<_>>(), Verb::ALL);
        for v in Verb::ALL {
            let w = v.name().as_str();
            for word in [w.to_string(), w.to_uppercase()] {
                let r = parse(word.as_bytes());
                assert!(matches!(r, Ok(_) | Err(CmdError::MissingArgument)), "{word}: {r:?}");
            }
        }
        assert_eq!(STOP_BYTE, b'!');
    }

    proptest! {
        #![proptest_config(cfg())]
        /// Lines of any length with any terminator: one result per line, the
        /// line itself when it fits, TooLong when not.
        #[test]
        fn line_buffer_model(lines in prop::collection::vec((prop::collection::vec(0x20u8..0x7f, 0..150), 0usize..3), 1..10)) {
            let mut lb = LineBuffer::<64>::new();
            let mut bytes = vec![];
            let mut want = vec![];
            let mut prev_cr = false;
            for (content, term) in &lines {
                bytes.extend_from_slice(content);
                bytes.extend_from_slice([&b"\n"[..], b"\r", b"\r\n"][*term]);
                // An empty line ended by \n right after a bare \r is the \n of a \r\n.
                if !(prev_cr && content.is_empty() && *term == 0) {
                    want.push(if content.len() <= 64 { Ok(content.clone()) } else { Err(CmdError::TooLong) });
                }
                prev_cr = *term == 1;
            }
            prop_assert_eq!(feed(&mut lb, &bytes), want);
        }
    }
}
