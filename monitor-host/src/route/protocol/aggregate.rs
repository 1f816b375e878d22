//! The protocols' aggregates over a set of routes (docs/PROTOCOLS.md): per protocol,
//! `driving_score` = Σ score / N, `route_completion` = Σ RC / N, `infraction_score` = Σ penalty
//! over the routes with a valid record / N under `lb2.0` and `lb2.1` (v1.4: as the
//! Leaderboard's global statistics compute it, so a route without a record weighs as 0) and the
//! mean penalty over those records under the others, `success_rate` = 100 × successes / N, and
//! for `f2d` the harmonic mean `hm` of DS and SR. f64, summed in the order the routes are given.
//!
//! ```
//! use monitor_host::route::protocol::aggregate::{harmonic_mean, ProtocolScores};
//! use monitor_host::route::protocol::route::{RouteProtocols, RouteScore};
//! use monitor_host::route::protocol::Protocol;
//! let route = RouteProtocols(vec![(Protocol::F2d, RouteScore { penalty: Some(0.5), score: 50.0, success: true, min_speed_events: 0 })]);
//! let missing = RouteProtocols::without_record(&[Protocol::F2d]);
//! let s = ProtocolScores::over([(100.0, &route), (0.0, &missing)], 2).unwrap();
//! let f2d = s.get(Protocol::F2d).unwrap();
//! assert_eq!((f2d.driving_score, f2d.route_completion), (Some(25.0), Some(50.0)));
//! assert_eq!((f2d.infraction_score, f2d.success_rate), (Some(0.5), Some(50.0)));
//! assert_eq!(f2d.hm, Some(harmonic_mean(25.0, 50.0)));
//! // Under the Leaderboard the missing route weighs in the infraction score: 0.5 / 2.
//! let route = RouteProtocols(vec![(Protocol::Lb21, RouteScore { penalty: Some(0.5), score: 50.0, success: true, min_speed_events: 0 })]);
//! let missing = RouteProtocols::without_record(&[Protocol::Lb21]);
//! let s = ProtocolScores::over([(100.0, &route), (0.0, &missing)], 2).unwrap();
//! assert_eq!(s.get(Protocol::Lb21).unwrap().infraction_score, Some(0.25));
//! assert_eq!(harmonic_mean(0.0, 50.0), 0.0);
//! ```

use serde::{Deserialize, Serialize};

use crate::route::protocol::route::RouteProtocols;
use crate::route::protocol::Protocol;

/// One protocol's aggregates over a set of routes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ProtocolAggregate {
    /// Σ score / N (0..100).
    pub driving_score: Option<f64>,
    /// Σ RC / N (0..100).
    pub route_completion: Option<f64>,
    /// Σ penalty over the routes with a valid record / N under `lb2.0` and `lb2.1`; the mean
    /// penalty over those routes under the others (0..1).
    pub infraction_score: Option<f64>,
    /// 100 × successes / N.
    pub success_rate: Option<f64>,
    /// `f2d` only: `2 / (1/DS + 1/SR)`, 0 when either is 0.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hm: Option<f64>,
}

/// `2 / (1/ds + 1/sr)`, 0 when either is 0.
pub fn harmonic_mean(ds: f64, sr: f64) -> f64 {
    if ds <= 0.0 || sr <= 0.0 {
        0.0
    } else {
        2.0 / (1.0 / ds + 1.0 / sr)
    }
}

/// Every asked protocol's aggregates, in [`Protocol::ALL`] order: the summary's and each
/// group's `protocols` object.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ProtocolScores(pub Vec<(Protocol, ProtocolAggregate)>);

impl ProtocolScores {
    /// The aggregates of `p`, when it was asked.
    pub fn get(&self, p: Protocol) -> Option<&ProtocolAggregate> {
        self.0.iter().find(|(q, _)| *q == p).map(|(_, a)| a)
    }

    /// The aggregates over `routes` — each route's RC (`score_route`, 0 without a record) and
    /// its protocol scores — over `n` routes. `None` when no route carries protocol scores
    /// (none were asked).
    pub fn over<'a, I>(routes: I, n: usize) -> Option<ProtocolScores>
    where
        I: IntoIterator<Item = (f64, &'a RouteProtocols)>,
    {
        #[derive(Default, Clone, Copy)]
        struct Sums {
            asked: bool,
            score: f64,
            rc: f64,
            penalty: f64,
            with_record: usize,
            successes: usize,
        }
        let mut sums = [Sums::default(); 5];
        for (rc, protocols) in routes {
            for (p, r) in &protocols.0 {
                let s = &mut sums[*p as usize];
                s.asked = true;
                s.score += r.score;
                s.rc += rc;
                if let Some(pen) = r.penalty {
                    s.penalty += pen;
                    s.with_record += 1;
                }
                s.successes += usize::from(r.success);
            }
        }
        let per = |x: f64| (n > 0).then(|| x / n as f64);
        let out: Vec<(Protocol, ProtocolAggregate)> = Protocol::ALL
            .into_iter()
            .zip(sums)
            .filter(|(_, s)| s.asked)
            .map(|(p, s)| {
                let ds = per(s.score);
                let sr = per(100.0 * s.successes as f64);
                let a = ProtocolAggregate {
                    driving_score: ds,
                    route_completion: per(s.rc),
                    infraction_score: match p {
                        // The Leaderboard's global statistics divide by every route (v1.4).
                        Protocol::Lb20 | Protocol::Lb21 => {
                            (s.with_record > 0).then_some(s.penalty).and_then(per)
                        }
                        _ => (s.with_record > 0).then(|| s.penalty / s.with_record as f64),
                    },
                    success_rate: sr,
                    hm: if p == Protocol::F2d {
                        ds.zip(sr).map(|(d, r)| harmonic_mean(d, r))
                    } else {
                        None
                    },
                };
                (p, a)
            })
            .collect();
        (!out.is_empty()).then_some(ProtocolScores(out))
    }
}

impl Serialize for ProtocolScores {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_map(self.0.iter().map(|(p, a)| (p.id(), a)))
    }
}

impl<'de> Deserialize<'de> for ProtocolScores {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        crate::named::pairs(d)?
            .into_iter()
            .map(|(id, a)| Ok((Protocol::of_key(&id)?, a)))
            .collect::<Result<_, _>>()
            .map(ProtocolScores)
    }
}
