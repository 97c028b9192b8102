//! Seeded random mutations of IGES files (the B-rep part, the trimmed
//! B-spline part and a hand-made file with every surface type): the reader
//! must return `Ok` or `Err`, never panic. `CMM_IGES_FUZZ_RUNS` sets the
//! mutations per source (default 300).
mod cad_iges_support;
use cad_iges_support::Iges;
use cmm::cad::{iges::import_iges, ImportOptions};
use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};

/// Bytes that steer mutations into interesting IGES syntax.
const SPICE: &[u8] = b",;.-+0123456789EDHSGPTX \n";

/// A part file from `$CMM_SHARED_CAD`, else `../shared/cad` beside the repository.
fn shared(name: &str) -> Option<Vec<u8>> {
    let dir = std::env::var("CMM_SHARED_CAD")
        .unwrap_or_else(|_| format!("{}/../shared/cad", env!("CARGO_MANIFEST_DIR")));
    std::fs::read(format!("{dir}/{name}")).ok()
}

/// A file with one entity of each supported kind.
fn sampler() -> Vec<u8> {
    let mut g = Iges::default();
    let c = g.add(116, 0, "1.,2.,3.,0");
    let z = g.add(123, 0, "0.,0.,1.");
    g.add(196, 0, &format!("{c},5."));
    g.add(198, 0, &format!("{c},{z},5.,1."));
    let axis = g.add(110, 0, "0.,0.,0.,0.,0.,1.");
    let line = g.add(110, 0, "3.,0.,0.,3.,0.,10.");
    g.add(120, 0, &format!("{axis},{line},0.,3."));
    let arc = g.add(100, 0, "0.,0.,0.,5.,0.,0.,5.");
    g.add(122, 0, &format!("{arc},5.,0.,7."));
    g.add(118, 1, &format!("{axis},{line},0,0"));
    let t = g.add(124, 0, "0.,-1.,0.,0.,1.,0.,0.,0.,0.,0.,1.,0.");
    let def = g.add(308, 0, &format!("0,1Ha,1,{arc}"));
    g.add_t(408, 0, &format!("{def},1.,2.,3.,2."), t);
    g.text().into_bytes()
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
fn iges_reader_never_panics_on_mutations() {
    let runs: usize = std::env::var("CMM_IGES_FUZZ_RUNS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(300);
    let mut sources = vec![sampler()];
    sources.extend(shared("io1-cm-214-brep.igs"));
    let mut rng = ChaCha8Rng::seed_from_u64(0x1E5_0001);
    let opts = ImportOptions::default();
    let (mut ok, mut err) = (0usize, 0usize);
    for src in &sources {
        for _ in 0..runs {
            let m = mutate(&mut rng, src);
            match import_iges(&String::from_utf8_lossy(&m), "fuzz.igs", "fuzz", &opts) {
                Ok(_) => ok += 1,
                Err(_) => err += 1,
            }
        }
    }
    println!("{} executions: {ok} Ok, {err} Err, no panic", ok + err);
    assert_eq!(ok + err, runs * sources.len());
}
