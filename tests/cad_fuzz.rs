//! Seeded random mutations of the real files: the STEP parser, the STEP
//! import and the IGES import must return (Ok or Err) and never panic.
use cmm::cad::{iges::import_iges, parse_step_str, step::import_step, ImportOptions};
use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};

/// Bytes that steer mutations into interesting syntax.
const SPICE: &[u8] = b"()#';,.\\$*/=0123456789EeXS\"\n ";

fn shared(name: &str) -> Option<Vec<u8>> {
    let p = format!("{}/../shared/cad/{name}", env!("CARGO_MANIFEST_DIR"));
    let bytes = std::fs::read(&p).ok();
    if bytes.is_none() {
        println!("note: {p} not found; skipping");
    }
    bytes
}

fn mutate(rng: &mut ChaCha8Rng, src: &[u8]) -> Vec<u8> {
    let mut b = src.to_vec();
    for _ in 0..rng.random_range(1..6usize) {
        if b.is_empty() {
            break;
        }
        let at = rng.random_range(0..b.len());
        match rng.random_range(0..6u32) {
            0 => b[at] = rng.random::<u8>(),
            1 => b[at] = SPICE[rng.random_range(0..SPICE.len())],
            2 => b.insert(at, SPICE[rng.random_range(0..SPICE.len())]),
            3 => {
                let end = (at + rng.random_range(1..64usize)).min(b.len());
                b.drain(at..end);
            }
            4 => {
                let end = (at + rng.random_range(1..256usize)).min(b.len());
                let chunk = b[at..end].to_vec();
                let to = rng.random_range(0..b.len());
                b.splice(to..to, chunk);
            }
            _ => b.truncate(at),
        }
    }
    b
}

#[test]
fn step_parser_never_panics() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5EED_0001);
    let sources: Vec<Vec<u8>> = ["abc-0000.step", "io1-cm-214.stp"]
        .iter()
        .filter_map(|n| shared(n))
        .collect();
    for src in &sources {
        for _ in 0..1500 {
            let m = mutate(&mut rng, src);
            let _ = parse_step_str(&String::from_utf8_lossy(&m));
        }
    }
}

#[test]
fn step_import_never_panics() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5EED_0002);
    let opts = ImportOptions::default();
    let sources: Vec<Vec<u8>> = ["abc-0000.step", "io1-cm-214.stp"]
        .iter()
        .filter_map(|n| shared(n))
        .collect();
    for src in &sources {
        for _ in 0..500 {
            let m = mutate(&mut rng, src);
            let _ = import_step(&String::from_utf8_lossy(&m), "fuzz.step", "fuzz", &opts);
        }
    }
}

#[test]
fn iges_import_never_panics() {
    let Some(src) = shared("bearing.iges") else {
        return;
    };
    let mut rng = ChaCha8Rng::seed_from_u64(0x5EED_0003);
    let opts = ImportOptions::default();
    for _ in 0..100 {
        let m = mutate(&mut rng, &src);
        let _ = import_iges(&String::from_utf8_lossy(&m), "fuzz.iges", "fuzz", &opts);
    }
}

#[test]
fn arbitrary_bytes_never_panic() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5EED_0004);
    for _ in 0..3000 {
        let len = rng.random_range(0..200usize);
        let bytes: Vec<u8> = (0..len)
            .map(|_| SPICE[rng.random_range(0..SPICE.len())])
            .collect();
        let text = format!(
            "ISO-10303-21;HEADER;ENDSEC;DATA;{}",
            String::from_utf8_lossy(&bytes)
        );
        let _ = parse_step_str(&text);
    }
}
