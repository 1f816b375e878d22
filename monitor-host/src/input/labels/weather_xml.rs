//! Bench2Drive's `weather.xml` as a weather label map. The file names no presets: each
//! `<case weather_id>` holds the parameters of its first `<weather>` keyframe, and the label is
//! built from them in the style of CARLA's preset names (`ClearNoon`, `HardRainSunset`,
//! `CloudyNight`, ...): the sky (`Clear` cloudiness < 30, `Cloudy` otherwise), rain (`Soft`/
//! `Mid`/`HardRain` for precipitation up to 30 / 60 / above), `Wet` ground (wetness > 0),
//! `Foggy` (fog density >= 50) and the time of day from the sun's altitude (`Night` below 0°,
//! `Sunset` below 15°, `Noon` from 15°).

use quick_xml::events::Event;
use quick_xml::Reader;

use super::Labels;
use super::LabelsError;

/// Parses `weather.xml` text into `weather_id → [label]`.
pub(super) fn parse(text: &str, file: &str) -> Result<Labels, LabelsError> {
    let err = |message: String| LabelsError::Xml {
        file: file.into(),
        message,
    };
    let mut reader = Reader::from_str(text);
    let mut labels = Labels::new();
    let mut case: Option<String> = None;
    loop {
        match reader.read_event().map_err(|e| err(e.to_string()))? {
            Event::Start(e) | Event::Empty(e) => match e.name().as_ref() {
                b"case" => {
                    case = attr(&e, b"weather_id");
                    if case.is_none() {
                        return Err(err("a <case> without weather_id".into()));
                    }
                }
                b"weather" => {
                    if let Some(id) = case.take() {
                        let p = |n: &[u8]| attr(&e, n).and_then(|v| v.trim().parse::<f64>().ok());
                        labels.insert(
                            id,
                            vec![label(
                                p(b"cloudiness").unwrap_or(0.0),
                                p(b"precipitation").unwrap_or(0.0),
                                p(b"wetness").unwrap_or(0.0),
                                p(b"fog_density").unwrap_or(0.0),
                                p(b"sun_altitude_angle").unwrap_or(90.0),
                            )],
                        );
                    }
                }
                _ => {}
            },
            Event::Eof => break,
            _ => {}
        }
    }
    if labels.is_empty() {
        return Err(err("no <case weather_id> with a <weather> found".into()));
    }
    Ok(labels)
}

fn attr(e: &quick_xml::events::BytesStart<'_>, name: &[u8]) -> Option<String> {
    e.attributes()
        .filter_map(Result::ok)
        .find(|a| a.key.as_ref() == name)
        .map(|a| String::from_utf8_lossy(&a.value).into_owned())
}

/// A CARLA-preset-style name of the parameters.
fn label(cloudiness: f64, precipitation: f64, wetness: f64, fog: f64, sun: f64) -> String {
    let mut s = String::new();
    if precipitation > 0.0 {
        s.push_str(if precipitation <= 30.0 {
            "SoftRain"
        } else if precipitation <= 60.0 {
            "MidRain"
        } else {
            "HardRain"
        });
    } else {
        if wetness > 0.0 {
            s.push_str("Wet");
        }
        s.push_str(if cloudiness < 30.0 { "Clear" } else { "Cloudy" });
    }
    if fog >= 50.0 {
        s.push_str("Foggy");
    }
    s.push_str(if sun < 0.0 {
        "Night"
    } else if sun < 15.0 {
        "Sunset"
    } else {
        "Noon"
    });
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_from_parameters() {
        let xml = r#"<weathers>
          <case weather_id="1"><weather route_percentage="0" cloudiness="5.0" precipitation="0.0"
            wetness="0.0" sun_altitude_angle="15.0" fog_density="2.0"/>
            <weather route_percentage="100" cloudiness="90.0"/></case>
          <case weather_id="2"><weather cloudiness="20" precipitation="30" wetness="0"
            sun_altitude_angle="45" fog_density="3"/></case>
          <case weather_id="25"><weather cloudiness="100" precipitation="100" wetness="100"
            sun_altitude_angle="-90" fog_density="100"/></case>
        </weathers>"#;
        let m = parse(xml, "w.xml").unwrap();
        assert_eq!(m["1"], ["ClearNoon"]);
        assert_eq!(m["2"], ["SoftRainNoon"]);
        assert_eq!(m["25"], ["HardRainFoggyNight"]);
        assert!(parse("<weathers/>", "w.xml").is_err());
    }
}
