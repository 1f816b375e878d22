//! Measures the stack a chunk end needs for a few capacities (docs/RELIABILITY.md, "Core").
//! `cargo run --release -p monitor-core --example stack_probe`
use monitor_core::{Collisions, Config, Frame, Monitor};

fn run<const N: usize>() {
    let config = Config {
        chunk_len: N as u16,
        decel_window: 20.min(N as u16),
        ..Config::DEFAULT
    };
    let mut m: Monitor<N> = Monitor::new(config).expect("valid");
    let f = Frame::from_vectors(
        [0.5, 0.1],
        [1.0, 0.0],
        [0.0, 1.0],
        3.0,
        5.0,
        Some(0.3),
        Collisions::NONE,
    );
    for _ in 0..(3 * N) {
        let _ = m.push(&f);
    }
    let _ = m.finish();
}

fn probe<const N: usize>() {
    // Smallest thread stack (4 KiB steps) that runs a route with chunk ends.
    let (mut lo, mut hi) = (4096usize, 64 << 20);
    while hi - lo > 4096 {
        let mid = (lo + hi) / 2 / 4096 * 4096;
        let ok = std::process::Command::new(std::env::current_exe().unwrap())
            .arg(N.to_string())
            .arg(mid.to_string())
            .status()
            .unwrap()
            .success();
        if ok {
            hi = mid
        } else {
            lo = mid
        }
    }
    println!(
        "N = {N:5}: size_of Monitor = {:7} B, chunk-end stack <= {:8} B",
        core::mem::size_of::<Monitor<N>>(),
        hi
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() == 3 {
        let n: usize = args[1].parse().unwrap();
        let stack: usize = args[2].parse().unwrap();
        let h = std::thread::Builder::new()
            .stack_size(stack)
            .spawn(move || match n {
                20 => run::<20>(),
                64 => run::<64>(),
                256 => run::<256>(),
                1024 => run::<1024>(),
                4096 => run::<4096>(),
                _ => unreachable!(),
            })
            .unwrap();
        std::process::exit(if h.join().is_ok() { 0 } else { 1 });
    }
    probe::<20>();
    probe::<64>();
    probe::<256>();
    probe::<1024>();
    probe::<4096>();
}
