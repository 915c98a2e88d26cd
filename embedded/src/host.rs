//! The firmware's loop on the host (`rhonn-core` built without `std`, as on the target):
//! prints the lines the firmware prints, for `run-qemu.sh` to compare.

use rhonn_firmware::{run, write_line, Digest, Regulation, PRINT_EVERY};

fn main() {
    let mut digest = Digest::default();
    let mut regulation = Regulation::default();
    let mut line = String::new();
    let done = run(
        |s| {
            digest.add(s);
            regulation.add(s);
            if s.k % PRINT_EVERY == 0 || s.k + 1 == rhonn_firmware::PERIODS {
                line.clear();
                write_line(&mut line, s).expect("writing to a String");
                println!("{line}");
            }
        },
        |_, step| step(),
    );
    if let Err(e) = done {
        eprintln!("host: {e}");
        std::process::exit(1);
    }
    println!("digest={:016x}", digest.0);
    println!(
        "regulation rms_error_mpa={:.6} max_abs_error_mpa={:.6} (from 1 s after each set-point change)",
        regulation.rms_mpa(),
        regulation.max_abs_mpa
    );
    println!(
        "online_identifier rms_error_mpa={:.6} persistence_rms_error_mpa={:.6} (estimate minus the plant's pressure, 5 to 10 s)",
        regulation.online_rms_mpa(),
        regulation.persistence_rms_mpa()
    );
}
