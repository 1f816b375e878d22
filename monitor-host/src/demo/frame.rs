//! The demo's simulated frames and the layouts of its large runs: what the scripts hand to the
//! telemetry writer.

/// One simulated frame in world coordinates.
pub(super) struct SimFrame {
    pub(super) loc: [f64; 2],
    pub(super) acc: [f64; 2],
    pub(super) speed: f64,
}

named_enum! {
    /// Which keys each frame of a large run's `metric_info.json` has (`sds demo --layout`).
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
    pub enum LargeLayout {
        /// Bench2Drive's own layout: the six keys its agents' `get_metric_info()` returns
        /// (`acceleration`, `angular_velocity`, `forward_vector`, `right_vector`, `location`,
        /// `rotation`), about 830 bytes per frame. What the throughput figures are measured on.
        #[default]
        Bench2Drive = "b2d",
        /// A wider frame of 13 keys (the six plus `velocity`, `speed`, `throttle`, `steer`, `brake`,
        /// `gps`, `compass`), about 1.26 KB per frame: more bytes to skip per number kept.
        Wide = "wide",
    }
}
