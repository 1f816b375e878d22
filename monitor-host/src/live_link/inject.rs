//! Deterministic fault injection on the bytes the checker receives (`--inject drop=P,
//! corrupt=P,duplicate=P,reorder=P,stall=SECONDS,seed=N`). Faults are drawn per frame message
//! from a generator seeded by `seed` and the route's place in the run, in a fixed order of
//! draws, so one seed gives the same bytes on every machine. Start and end messages are not
//! injected: they are repeated until answered, so a lost one only costs a repeat.

/// The fault plan's parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Inject {
    /// Probability that a frame message is lost.
    pub drop: f64,
    /// Probability that 1 to 3 of its bytes are changed.
    pub corrupt: f64,
    /// Probability that it arrives twice.
    pub duplicate: f64,
    /// Probability that it is held back and arrives after the next one.
    pub reorder: f64,
    /// Once per route, at a frame drawn from the seed, the cable is pulled for this long: the
    /// frames of that time are lost and nothing arrives (0: never).
    pub stall: f64,
    /// The generator's seed.
    pub seed: u64,
}

/// Why `--inject` does not parse.
#[derive(Debug, thiserror::Error)]
#[error("--inject {given}: {why} (expected drop=P,corrupt=P,duplicate=P,reorder=P,stall=SECONDS,seed=N; P in 0..=1)")]
pub struct InjectError {
    given: String,
    why: String,
}

impl std::str::FromStr for Inject {
    type Err = InjectError;

    /// ```
    /// let i: monitor_host::live_link::Inject = "drop=0.05,seed=7".parse().unwrap();
    /// assert_eq!((i.drop, i.seed, i.corrupt), (0.05, 7, 0.0));
    /// assert!("drop=2".parse::<monitor_host::live_link::Inject>().is_err());
    /// ```
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let err = |why: String| InjectError {
            given: s.to_string(),
            why,
        };
        let mut i = Inject::default();
        for part in s.split(',').filter(|p| !p.trim().is_empty()) {
            let (k, v) = part
                .split_once('=')
                .ok_or_else(|| err(format!("{part}: no '='")))?;
            let (k, v) = (k.trim(), v.trim());
            if k == "seed" {
                i.seed = v.parse().map_err(|_| err(format!("seed={v}: not a u64")))?;
                continue;
            }
            let x: f64 = v
                .parse()
                .ok()
                .filter(|x: &f64| x.is_finite() && *x >= 0.0)
                .ok_or_else(|| err(format!("{k}={v}: not a number >= 0")))?;
            let p = |x: f64| {
                if x <= 1.0 {
                    Ok(x)
                } else {
                    Err(err(format!("{k}={v}: a probability is at most 1")))
                }
            };
            match k {
                "drop" => i.drop = p(x)?,
                "corrupt" => i.corrupt = p(x)?,
                "duplicate" => i.duplicate = p(x)?,
                "reorder" => i.reorder = p(x)?,
                "stall" => i.stall = x.min(3600.0),
                _ => return Err(err(format!("{k}: no such fault"))),
            }
        }
        Ok(i)
    }
}

impl Inject {
    /// No fault at all.
    pub fn is_none(&self) -> bool {
        self.drop == 0.0
            && self.corrupt == 0.0
            && self.duplicate == 0.0
            && self.reorder == 0.0
            && self.stall == 0.0
    }

    /// The fault plan of the route at `route_index` of the run, with `frames` frames of period
    /// `dt`.
    pub fn plan(&self, route_index: usize, frames: usize, dt: f64) -> Plan {
        let mut rng =
            SplitMix64(self.seed ^ (route_index as u64).wrapping_mul(0xA076_1D64_78BD_642F));
        let (stall_at, stall_frames) = if self.stall > 0.0 && frames > 0 {
            let at = (rng.next() % frames as u64) as usize;
            (at, (self.stall / dt).ceil() as usize)
        } else {
            (usize::MAX, 0)
        };
        Plan {
            inject: *self,
            rng,
            stall_at,
            stall_frames,
            held: None,
        }
    }
}

/// SplitMix64: small, fast, and the same sequence everywhere.
#[derive(Clone, Debug)]
struct SplitMix64(u64);

impl SplitMix64 {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// What reaches the wire for one frame message.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Sent {
    /// Pause before writing, seconds (the stall).
    pub pause: f64,
    /// Pieces written in order, each with the counter of its frame when it is that frame's
    /// message unchanged.
    pub pieces: Vec<(Vec<u8>, Option<u16>)>,
}

/// One route's faults, drawn frame by frame.
#[derive(Clone, Debug)]
pub struct Plan {
    inject: Inject,
    rng: SplitMix64,
    stall_at: usize,
    stall_frames: usize,
    held: Option<(Vec<u8>, u16)>,
}

impl Plan {
    /// The bytes to send for frame `index`, whose encoded message is `bytes` with counter
    /// `counter`.
    pub fn frame(&mut self, index: usize, counter: u16, bytes: &[u8]) -> Sent {
        let mut sent = Sent::default();
        if index >= self.stall_at && index < self.stall_at.saturating_add(self.stall_frames) {
            if index == self.stall_at {
                sent.pause = self.inject.stall;
            }
            return sent;
        }
        let i = self.inject;
        // Every draw is made whatever the probabilities, so one fault's rate does not move the
        // others' draws.
        let (d, c, u, r) = (
            self.rng.unit(),
            self.rng.unit(),
            self.rng.unit(),
            self.rng.unit(),
        );
        let hits: Vec<(u64, u8)> = (0..3)
            .map(|_| (self.rng.next(), (self.rng.next() % 255 + 1) as u8))
            .collect();
        let n_hits = (self.rng.next() % 3 + 1) as usize;
        if d < i.drop {
            return self.release(sent);
        }
        let mut piece = (bytes.to_vec(), Some(counter));
        if c < i.corrupt {
            let mut done = Vec::new();
            for (pos, x) in hits.iter().take(n_hits) {
                let p = (*pos % bytes.len().max(1) as u64) as usize;
                if !done.contains(&p) {
                    if let Some(b) = piece.0.get_mut(p) {
                        *b ^= x;
                    }
                    done.push(p);
                }
            }
            piece.1 = None;
        }
        if r < i.reorder && self.held.is_none() {
            // Held back: it goes after the next message.
            self.held = Some((piece.0.clone(), counter));
            if u < i.duplicate {
                sent.pieces.push(piece);
            }
            return sent;
        }
        sent.pieces.push(piece.clone());
        if u < i.duplicate {
            sent.pieces.push(piece);
        }
        self.release(sent)
    }

    fn release(&mut self, mut sent: Sent) -> Sent {
        if let Some((b, c)) = self.held.take() {
            // A held message is intact unless it was corrupted; its counter says which frame.
            let intact = intact(&b, c);
            sent.pieces.push((b, intact));
        }
        sent
    }

    /// A message still held back at the route's end (sent before the end message).
    pub fn flush(&mut self) -> Sent {
        self.release(Sent::default())
    }
}

/// `Some(counter)` when `bytes` is the unchanged frame message of that counter.
fn intact(bytes: &[u8], counter: u16) -> Option<u16> {
    let mut rx = monitor_core::link::Deframer::new();
    let mut ok = false;
    for &b in bytes {
        if let Some(Ok(m)) = rx.push(b) {
            ok |= monitor_core::link::decode(m).is_ok_and(|(h, _)| h.counter == counter);
        }
    }
    ok.then_some(counter)
}
