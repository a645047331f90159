// Reads a gcsv file with Gyroflow's telemetry-parser and prints what it found: per sensor
// "<name> <count> <scale> <orientation>" and then "<name>_row <t> <x> <y> <z>" for every sample,
// numbers in Rust's shortest round-trip form, for the export test to compare to the last digit.
use std::sync::{atomic::AtomicBool, Arc};
use telemetry_parser::tags_impl::*;
use telemetry_parser::*;

fn main() {
    let path = std::env::args().nth(1).expect("usage: gcsv-reader FILE.gcsv");
    let mut file = std::fs::File::open(&path).expect("open");
    let size = file.metadata().expect("metadata").len() as usize;
    let input = Input::from_stream(&mut file, size, &path, |_| (), Arc::new(AtomicBool::new(false))).expect("parse");
    println!("camera {}", input.camera_type());
    for info in input.samples.as_ref().expect("samples") {
        let Some(map) = info.tag_map.as_ref() else { continue };
        for (group, name) in [(GroupId::Gyroscope, "gyro"), (GroupId::Accelerometer, "accl"), (GroupId::Magnetometer, "magn")] {
            let Some(m) = map.get(&group) else { continue };
            let scale = (m.get_t(TagId::Scale) as Option<&f64>).copied().unwrap_or(f64::NAN);
            let orientation = (m.get_t(TagId::Orientation) as Option<&String>).cloned().unwrap_or_default();
            let Some(data) = m.get_t(TagId::Data) as Option<&Vec<TimeVector3<f64>>> else { continue };
            println!("{} {} {:?} {}", name, data.len(), scale, orientation);
            for v in data {
                println!("{}_row {:?} {:?} {:?} {:?}", name, v.t, v.x, v.y, v.z);
            }
        }
    }
}
