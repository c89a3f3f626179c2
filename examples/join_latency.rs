//! How long a `rayon::join` of two equal tasks takes when it is called from outside the pool
//! (each call hands the work to workers that may be asleep), from inside it (the caller is a
//! worker), and with two scoped threads, against the two tasks in series; a short serial
//! stretch follows each join, as the Newton step follows each shooting linearisation.
//! `cargo run --release --example join_latency` (2 threads). The continuation runs on a pool
//! worker because of what this measured (`critspeed::continuation::Continuation::run`).

use std::time::Instant;

/// About `n` ns of arithmetic that the optimiser cannot remove.
fn spin(n: u64) -> u64 {
    let mut s = 0u64;
    for i in 0..n {
        s = s.wrapping_add(std::hint::black_box(i * i));
    }
    s
}

fn main() {
    let pool = match rayon::ThreadPoolBuilder::new().num_threads(2).build() {
        Ok(p) => p,
        Err(e) => {
            eprintln!("no thread pool: {e}");
            return;
        }
    };
    let reps = 300;
    for work in [100_000u64, 1_000_000] {
        let per = |t: Instant| t.elapsed().as_secs_f64() / reps as f64 * 1e6;
        let t = Instant::now();
        for _ in 0..reps {
            std::hint::black_box((spin(work), spin(work), spin(work / 20)));
        }
        let serial = per(t);
        let t = Instant::now();
        for _ in 0..reps {
            std::hint::black_box(pool.install(|| rayon::join(|| spin(work), || spin(work))));
            std::hint::black_box(spin(work / 20));
        }
        let outside = per(t);
        let t = Instant::now();
        pool.install(|| {
            for _ in 0..reps {
                std::hint::black_box(rayon::join(|| spin(work), || spin(work)));
                std::hint::black_box(spin(work / 20));
            }
        });
        let inside = per(t);
        let t = Instant::now();
        for _ in 0..reps {
            std::thread::scope(|s| {
                let a = s.spawn(|| spin(work));
                std::hint::black_box((spin(work), a.join().is_ok()));
            });
            std::hint::black_box(spin(work / 20));
        }
        let scoped = per(t);
        println!(
            "two tasks of {work} iterations: in series {serial:.0} us; join from outside the pool \
             {outside:.0} us ({:.2}x); from a worker {inside:.0} us ({:.2}x); scoped threads \
             {scoped:.0} us ({:.2}x)",
            serial / outside,
            serial / inside,
            serial / scoped
        );
    }
}
