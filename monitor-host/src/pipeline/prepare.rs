//! Prepare: a record and its telemetry → the monitor's frames (docs/SCORE.md §3, docs/SCORE.md §6).
//!
//! Signals come from the raw vectors through the core's f32 kernels; speed, lateral error and
//! collision alignment are computed in f64 on the raw coordinates and rounded to f32 once, when
//! the [`Frame`] is built.

use monitor_core::{Collisions, Frame};

use crate::geometry::corridor::{Corridor, LateralSample, ReferenceKind};
use crate::geometry::map::Map;
use crate::input::collision::{self, CollisionList};
use crate::input::lead_infractions::StepInfraction;
use crate::input::record::Record;
use crate::input::route_xml::{RouteRef, RouteSet};
use crate::input::telemetry::Telemetry;
use crate::pipeline::align::{self, EventRef};
use crate::pipeline::live::LiveFrames;
use crate::pipeline::motion::{self, Motion};
use crate::pipeline::outcome::CollisionEvent;
use crate::pipeline::placement::{self, PlacedEvent};
use crate::settings::{decimal, Settings};

/// Parses a record's collision lists into events (not yet aligned).
pub fn collision_events(record: &Record) -> Vec<CollisionEvent> {
    let mut out = Vec::new();
    for list in CollisionList::ALL {
        for s in record.infractions.list(list.name()) {
            let (type_id, workzone, loc, parse_error) = match collision::parse_collision(s) {
                Ok(c) => {
                    let wz = list == CollisionList::Layout && collision::is_workzone(&c.type_id);
                    (Some(c.type_id), wz, c.location.map(|l| [l[0], l[1]]), None)
                }
                Err(e) => (None, false, None, Some(e.to_string())),
            };
            out.push(CollisionEvent {
                list,
                type_id,
                workzone,
                frame: None,
                step: None,
                aligned_by: None,
                time_s: None,
                impact_speed: None,
                decelerated: None,
                exempt: None,
                parse_error,
                message: s.clone(),
                location: loc,
            });
        }
    }
    out
}

/// The frames the monitor sees for a route, and the events aligned to them.
#[derive(Clone, Debug)]
pub struct PreparedRoute {
    /// One frame per telemetry step, in step order.
    pub frames: Vec<Frame>,
    /// Step number of each frame.
    pub steps: Vec<u64>,
    /// Collision events, aligned where possible.
    pub events: Vec<CollisionEvent>,
    /// What the lateral error was measured against.
    pub reference: ReferenceKind,
    /// Distance, stationary share and moving chunks (docs/SCORE.md §10.0).
    pub motion: Motion,
    /// The record's other infractions and the long stationary stretches, placed on the frames
    /// where possible ([`placement`]).
    pub placed: Vec<PlacedEvent>,
    /// Per frame, the host-side lateral values behind the frame's `lat_err` (`None` where it is
    /// unknown); empty unless asked for ([`prepare_with`]), as scoring does not need them.
    pub lateral: Vec<Option<LateralSample>>,
    /// The index of each segment's first frame (a vehicle log cut at its gaps, docs/SCORE.md §2.4:
    /// each segment streams through a fresh monitor); empty for one run of frames.
    pub segments: Vec<usize>,
}

/// Builds the monitor's frames: signals from the raw vectors (f32 kernels), speed, lateral error
/// (against the route or, with the town's `map`, the lane corridor: [`Corridor`]) and alignment
/// in f64, then rounded to f32 once.
pub fn prepare(
    record: &Record,
    tel: &Telemetry,
    routes: Option<&RouteSet>,
    map: Option<&Map>,
    infractions: Option<&[StepInfraction]>,
    settings: &Settings,
) -> PreparedRoute {
    prepare_with(record, tel, routes, map, infractions, settings, false)
}

/// [`prepare`], keeping each frame's [`LateralSample`] when `keep_lateral` (for `sds frames`).
pub fn prepare_with(
    record: &Record,
    tel: &Telemetry,
    routes: Option<&RouteSet>,
    map: Option<&Map>,
    infractions: Option<&[StepInfraction]>,
    settings: &Settings,
    keep_lateral: bool,
) -> PreparedRoute {
    let reference = routes.and_then(|r| record.xml_id().and_then(|id| r.get(id)));
    prepare_on(
        record,
        tel,
        reference,
        map,
        infractions,
        settings,
        keep_lateral,
    )
}

/// [`prepare_with`] against a reference given directly (a vehicle log's path, docs/SCORE.md §2.4)
/// rather than looked up in a route XML by the record's id.
pub fn prepare_on(
    record: &Record,
    tel: &Telemetry,
    reference: Option<&RouteRef>,
    map: Option<&Map>,
    infractions: Option<&[StepInfraction]>,
    settings: &Settings,
    keep_lateral: bool,
) -> PreparedRoute {
    let n = tel.frames.len();
    let steps = tel.steps();
    let locations = tel.locations();

    let corridor = Corridor::new(reference, map, settings);

    let parsed = collision_events(record);
    let refs: Vec<EventRef> = parsed
        .iter()
        .map(|e| EventRef {
            message: &e.message,
            location: e.location,
        })
        .collect();
    let aligned = align::align_events(
        &refs,
        &steps,
        &locations,
        infractions,
        settings.align_max_dist,
        settings.align_tie,
    );
    let mut collisions = vec![Collisions::NONE; n];
    let mut events = Vec::with_capacity(parsed.len());
    for (mut ev, a) in parsed.into_iter().zip(aligned) {
        if let Some(k) = a.frame.filter(|&k| k < n) {
            ev.list.count_in(ev.workzone, &mut collisions[k]);
            ev.frame = Some(k);
            ev.step = Some(steps[k]);
            ev.aligned_by = a.by;
            ev.time_s = Some((steps[k] - steps[0]) as f64 * decimal(settings.core.dt));
        }
        events.push(ev);
    }

    let motion = motion::measure_segments(
        &locations,
        &steps,
        &tel.segments,
        decimal(settings.core.dt),
        &settings.motion,
        usize::from(settings.core.chunk_len),
        usize::from(settings.core.min_chunk),
    );
    let dt = decimal(settings.core.dt);
    let mut placed = placement::infraction_events(&record.infractions);
    placement::place(&mut placed, &steps, &locations, infractions, settings, dt);
    placed.extend(placement::standing_events(
        &motion.stationary,
        &steps,
        settings,
        dt,
    ));
    let mut live = LiveFrames::with_corridor(corridor, settings.core.dt);
    let mut lateral = Vec::with_capacity(if keep_lateral { n } else { 0 });
    let mut starts = tel.segments.iter().peekable();
    let frames: Vec<Frame> = tel
        .frames
        .iter()
        .zip(collisions)
        .enumerate()
        .map(|(i, (f, c))| {
            // A vehicle log's segment starts afresh (docs/SCORE.md §2.4).
            if starts.next_if(|&&s| s == i).is_some() {
                live.start_segment();
            }
            let (frame, sample) = live.build(f, c);
            if keep_lateral {
                lateral.push(sample);
            }
            frame
        })
        .collect();
    // The impact speed is the frame's speed (f64, rounded to f32 once).
    for ev in &mut events {
        ev.impact_speed = ev.frame.map(|k| frames[k].speed);
    }
    PreparedRoute {
        frames,
        steps,
        events,
        reference: live.reference(),
        lateral,
        motion,
        placed,
        segments: tel.segments.clone(),
    }
}
