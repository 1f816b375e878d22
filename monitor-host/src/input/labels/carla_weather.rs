//! CARLA's weather presets (`carla.WeatherParameters.ClearNoon`, ...), as CARLA 0.9.15 and
//! 0.9.16 define them, every parameter: the names [`super::weather_xml`] gives to the cases of
//! Bench2Drive's `weather.xml`. A test checks the table against the `carla` Python package when
//! it is installed (the venv of `scripts/map-crosscheck.sh`).

/// The parameters of a preset, in this order (CARLA's names).
pub const PARAMETERS: [&str; 14] = [
    "cloudiness",
    "precipitation",
    "precipitation_deposits",
    "wind_intensity",
    "sun_azimuth_angle",
    "sun_altitude_angle",
    "fog_density",
    "fog_distance",
    "wetness",
    "fog_falloff",
    "scattering_intensity",
    "mie_scattering_scale",
    "rayleigh_scattering_scale",
    "dust_storm",
];

/// Every preset of `carla.WeatherParameters`, by name, its parameters in [`PARAMETERS`] order
/// (CARLA stores them as f32). `Default` (every parameter -1: keep the current weather) names
/// no weather.
#[rustfmt::skip]
pub const PRESETS: [(&str, [f32; 14]); 23] = [
    ("ClearNight", [5.0, 0.0, 0.0, 10.0, -1.0, -90.0, 60.0, 75.0, 0.0, 1.0, 1.0, 0.03, 0.0331, 0.0]),
    ("ClearNoon", [5.0, 0.0, 0.0, 10.0, -1.0, 45.0, 2.0, 0.75, 0.0, 0.1, 1.0, 0.03, 0.0331, 0.0]),
    ("ClearSunset", [5.0, 0.0, 0.0, 10.0, -1.0, 15.0, 2.0, 0.75, 0.0, 0.1, 1.0, 0.03, 0.0331, 0.0]),
    ("CloudyNight", [60.0, 0.0, 0.0, 10.0, -1.0, -90.0, 60.0, 0.75, 0.0, 0.1, 1.0, 0.03, 0.0331, 0.0]),
    ("CloudyNoon", [60.0, 0.0, 0.0, 10.0, -1.0, 45.0, 3.0, 0.75, 0.0, 0.1, 1.0, 0.03, 0.0331, 0.0]),
    ("CloudySunset", [60.0, 0.0, 0.0, 10.0, -1.0, 15.0, 3.0, 0.75, 0.0, 0.1, 1.0, 0.03, 0.0331, 0.0]),
    ("Default", [-1.0, -1.0, -1.0, -1.0, -1.0, -1.0, -1.0, -1.0, -1.0, -1.0, 1.0, 0.03, 0.0331, 0.0]),
    ("DustStorm", [100.0, 0.0, 0.0, 100.0, -1.0, 45.0, 2.0, 0.75, 0.0, 0.1, 1.0, 0.03, 0.0331, 100.0]),
    ("HardRainNight", [100.0, 100.0, 90.0, 100.0, -1.0, -90.0, 100.0, 0.75, 100.0, 0.1, 1.0, 0.03, 0.0331, 0.0]),
    ("HardRainNoon", [100.0, 100.0, 90.0, 100.0, -1.0, 45.0, 7.0, 0.75, 0.0, 0.1, 1.0, 0.03, 0.0331, 0.0]),
    ("HardRainSunset", [100.0, 100.0, 90.0, 100.0, -1.0, 15.0, 7.0, 0.75, 0.0, 0.1, 1.0, 0.03, 0.0331, 0.0]),
    ("MidRainSunset", [60.0, 60.0, 60.0, 60.0, -1.0, 15.0, 3.0, 0.75, 0.0, 0.1, 1.0, 0.03, 0.0331, 0.0]),
    ("MidRainyNight", [80.0, 60.0, 60.0, 60.0, -1.0, -90.0, 60.0, 0.75, 80.0, 0.1, 1.0, 0.03, 0.0331, 0.0]),
    ("MidRainyNoon", [60.0, 60.0, 60.0, 60.0, -1.0, 45.0, 3.0, 0.75, 0.0, 0.1, 1.0, 0.03, 0.0331, 0.0]),
    ("SoftRainNight", [60.0, 30.0, 50.0, 30.0, -1.0, -90.0, 60.0, 0.75, 60.0, 0.1, 1.0, 0.03, 0.0331, 0.0]),
    ("SoftRainNoon", [20.0, 30.0, 50.0, 30.0, -1.0, 45.0, 3.0, 0.75, 0.0, 0.1, 1.0, 0.03, 0.0331, 0.0]),
    ("SoftRainSunset", [20.0, 30.0, 50.0, 30.0, -1.0, 15.0, 2.0, 0.75, 0.0, 0.1, 1.0, 0.03, 0.0331, 0.0]),
    ("WetCloudyNight", [60.0, 0.0, 50.0, 10.0, -1.0, -90.0, 60.0, 0.75, 60.0, 0.1, 1.0, 0.03, 0.0331, 0.0]),
    ("WetCloudyNoon", [60.0, 0.0, 50.0, 10.0, -1.0, 45.0, 3.0, 0.75, 0.0, 0.1, 1.0, 0.03, 0.0331, 0.0]),
    ("WetCloudySunset", [60.0, 0.0, 50.0, 10.0, -1.0, 15.0, 2.0, 0.75, 0.0, 0.1, 1.0, 0.03, 0.0331, 0.0]),
    ("WetNight", [5.0, 0.0, 50.0, 10.0, -1.0, -90.0, 60.0, 75.0, 60.0, 1.0, 1.0, 0.03, 0.0331, 0.0]),
    ("WetNoon", [5.0, 0.0, 50.0, 10.0, -1.0, 45.0, 3.0, 0.75, 0.0, 0.1, 1.0, 0.03, 0.0331, 0.0]),
    ("WetSunset", [5.0, 0.0, 50.0, 10.0, -1.0, 15.0, 2.0, 0.75, 0.0, 0.1, 1.0, 0.03, 0.0331, 0.0]),
];

/// The preset every given parameter of which equals the preset's (as CARLA's f32), `Default`
/// excepted; `None` when none does or nothing is given. Parameters not given are not compared.
///
/// ```
/// use monitor_host::input::labels::carla_weather::preset_of;
/// let p = [("cloudiness", 5.0), ("sun_altitude_angle", 15.0), ("fog_density", 2.0)];
/// assert_eq!(preset_of(&p), Some("ClearSunset"));
/// assert_eq!(preset_of(&[("cloudiness", 5.0), ("sun_altitude_angle", 90.0)]), None);
/// ```
pub fn preset_of(given: &[(&str, f64)]) -> Option<&'static str> {
    if given.is_empty() {
        return None;
    }
    PRESETS
        .iter()
        .filter(|(name, _)| *name != "Default")
        .find(|(_, values)| {
            given.iter().all(|(param, v)| {
                PARAMETERS
                    .iter()
                    .position(|p| p == param)
                    .is_some_and(|i| values[i] == *v as f32)
            })
        })
        .map(|(name, _)| *name)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;
    use std::process::Command;

    /// The Python of the map cross-check's venv (`SDS_CARLA_PYTHON` overrides it).
    fn carla_python() -> PathBuf {
        if let Some(p) = std::env::var_os("SDS_CARLA_PYTHON") {
            return p.into();
        }
        let target = std::env::var_os("CARGO_TARGET_DIR").map_or_else(
            || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target"),
            PathBuf::from,
        );
        target.join("map-crosscheck/venv/bin/python")
    }

    #[test]
    fn the_table_is_carlas_every_preset_every_parameter() {
        let python = carla_python();
        let script = format!(
            "import carla, json\nW = carla.WeatherParameters\nps = {:?}\n\
             print(json.dumps({{n: [getattr(getattr(W, n), p) for p in ps] for n in dir(W) \
             if isinstance(getattr(W, n), W)}}))",
            PARAMETERS.to_vec()
        );
        let out = Command::new(&python).args(["-c", &script]).output();
        let out = match out {
            Ok(o) if o.status.success() => o,
            _ => {
                eprintln!(
                    "############################################################\n\
                     ## SKIP the_table_is_carlas_every_preset_every_parameter: no `carla` \
                     Python package at {} (run scripts/map-crosscheck.sh once, or set \
                     SDS_CARLA_PYTHON)\n\
                     ############################################################",
                    python.display()
                );
                return;
            }
        };
        let carla: std::collections::BTreeMap<String, Vec<f64>> =
            serde_json::from_slice(&out.stdout).unwrap();
        let ours: Vec<&str> = PRESETS.iter().map(|(n, _)| *n).collect();
        let theirs: Vec<&str> = carla.keys().map(String::as_str).collect();
        assert_eq!(ours, theirs, "the same presets, in name order");
        for (name, values) in PRESETS {
            for (i, p) in PARAMETERS.iter().enumerate() {
                assert_eq!(
                    values[i], carla[name][i] as f32,
                    "carla.WeatherParameters.{name}.{p}"
                );
            }
        }
    }

    #[test]
    fn names() {
        assert_eq!(preset_of(&[]), None);
        // Bench2Drive's id 22: ClearNight by every parameter weather.xml gives.
        let id22 = [
            ("cloudiness", 5.0),
            ("precipitation", 0.0),
            ("precipitation_deposits", 0.0),
            ("wetness", 0.0),
            ("wind_intensity", 10.0),
            ("sun_azimuth_angle", -1.0),
            ("sun_altitude_angle", -90.0),
            ("fog_density", 60.0),
        ];
        assert_eq!(preset_of(&id22), Some("ClearNight"));
        // An unknown parameter matches nothing.
        assert_eq!(preset_of(&[("cloudiness", 5.0), ("rain", 0.0)]), None);
    }
}
