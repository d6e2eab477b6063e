//! Which display controller the boot probe's answers identify
//! (`ui::controller`): the IDs each datasheet gives, the order the probe
//! trusts them in, and everything else unknown. The bus side (who answers
//! what, and the firmware's reads) is tested in simavr
//! (`hal-sim/rig/tests/lcd_controllers.rs`).

use touch_arm::ui::controller::{Controller, IdReads, Protocol};
use touch_arm::ui::Layout;

/// Nothing answered: the pulled-up data lines read ones.
const SILENT: IdReads = IdReads { reg00: [0xFF; 2], id4: [0xFF; 4], rddid: [0xFF; 4] };

#[test]
fn each_datasheet_id_picks_its_controller() {
    // ILI9325 datasheet, R00h: 9325h.
    assert_eq!(IdReads { reg00: [0x93, 0x25], ..SILENT }.identify(), Some(Controller::Ili9325));
    // ILI9341 / ILI9486 datasheets, Read ID4 (D3h): dummy, 00h, 93h 41h / 94h 86h.
    assert_eq!(IdReads { id4: [0x5A, 0x00, 0x93, 0x41], ..SILENT }.identify(), Some(Controller::Ili9341));
    assert_eq!(IdReads { id4: [0x00, 0x00, 0x94, 0x86], ..SILENT }.identify(), Some(Controller::Ili9486));
    // ST7796S datasheet, Read ID4 (D3h): dummy, 00h, 77h 96h.
    assert_eq!(IdReads { id4: [0x00, 0x00, 0x77, 0x96], ..SILENT }.identify(), Some(Controller::St7796));
    // ST7789V datasheet, RDDID (04h): dummy, 85h 85h 52h.
    assert_eq!(IdReads { rddid: [0x00, 0x85, 0x85, 0x52], ..SILENT }.identify(), Some(Controller::St7789));
    // What each prints is what it answered.
    for c in Controller::ALL {
        let shown = match c {
            Controller::Ili9341 => 0x9341,
            Controller::St7789 => 0x85_8552,
            Controller::Ili9486 => 0x9486,
            Controller::Ili9325 => 0x9325,
            Controller::St7796 => 0x7796,
        };
        assert_eq!(c.id(), shown);
    }
}

#[test]
fn the_probe_trusts_register_0000h_then_read_id4_then_rddid() {
    // An ILI9325 answers something on D3h and 04h too (its registers D3h
    // and 04h): R00h decides.
    let ili9325 = IdReads { reg00: [0x93, 0x25], id4: [0, 0, 0x93, 0x41], rddid: [0, 0x85, 0x85, 0x52] };
    assert_eq!(ili9325.identify(), Some(Controller::Ili9325));
    let both = IdReads { id4: [0, 0x00, 0x94, 0x86], rddid: [0, 0x85, 0x85, 0x52], ..SILENT };
    assert_eq!(both.identify(), Some(Controller::Ili9486));
}

#[test]
fn anything_else_is_unknown() {
    for ids in [
        SILENT,
        IdReads { reg00: [0; 2], id4: [0; 4], rddid: [0; 4] },
        // The dummy byte in the wrong place.
        IdReads { id4: [0x00, 0x93, 0x41, 0xFF], ..SILENT },
        // Another IC version, another model.
        IdReads { id4: [0x00, 0x01, 0x93, 0x41], ..SILENT },
        IdReads { id4: [0x00, 0x00, 0x94, 0x88], ..SILENT },
        IdReads { reg00: [0x93, 0x28], ..SILENT },
        IdReads { id4: [0x00, 0x00, 0x77, 0x89], ..SILENT },
        IdReads { rddid: [0x85, 0x85, 0x52, 0x00], ..SILENT },
    ] {
        assert_eq!(ids.identify(), None, "{ids:?}");
    }
    let ids = IdReads { reg00: [0x12, 0x34], id4: [0xAA, 0x00, 0x93, 0x40], rddid: [0xAA, 0x01, 0x02, 0x03] };
    assert_eq!((ids.reg00_value(), ids.id4_value(), ids.rddid_value()), (0x1234, 0x009340, 0x010203));
}

#[test]
fn sizes_layouts_and_protocols() {
    for c in Controller::ALL {
        let (w, h) = c.size();
        assert_eq!(Layout::for_size(w, h), Some(c.layout()));
        assert_eq!(c.protocol() == Protocol::Indexed, c == Controller::Ili9325);
    }
    assert_eq!(Controller::Ili9486.size(), (480, 320));
    assert_eq!(Controller::St7796.size(), (480, 320));
    assert_eq!(Controller::St7796.layout(), Layout::HVGA);
    let names: Vec<String> = Controller::ALL.iter().map(|c| c.name().bytes().map(char::from).collect()).collect();
    assert_eq!(names, ["ili9341", "st7789", "ili9486", "ili9325", "st7796"]);
}

/// `cal set lcd <name>` forces each controller by its own name; `auto`
/// forces none.
#[test]
fn each_controller_is_forced_by_its_name() {
    use touch_arm::config::lcd::LcdChoice;
    assert_eq!(Controller::forced(LcdChoice::Auto), None);
    for c in Controller::ALL {
        assert_eq!(Controller::forced(c.choice()), Some(c));
        assert_eq!(c.choice().name(), c.name());
    }
    assert_eq!(LcdChoice::ALL.len(), Controller::ALL.len() + 1);
}
