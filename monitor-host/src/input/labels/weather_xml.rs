//! Bench2Drive's `weather.xml` as a weather label map. The file names no presets: each
//! `<case weather_id>` holds `<weather>` keyframes of CARLA weather parameters. A case is named
//! after the CARLA preset ([`super::carla_weather`]) every parameter it gives equals, in every
//! keyframe (`ClearNoon`, `HardRainSunset`, ...); a case that is no preset keeps its id as its
//! label (Bench2Drive's 23 cases: 10 presets, 13 ids).

use quick_xml::events::Event;
use quick_xml::Reader;

use super::carla_weather::preset_of;
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
                    if let Some(id) = &case {
                        let given: Vec<(String, f64)> = e
                            .attributes()
                            .filter_map(Result::ok)
                            .filter(|a| a.key.as_ref() != b"route_percentage")
                            .map(|a| {
                                // A value that is no number matches no preset.
                                let v = String::from_utf8_lossy(&a.value).trim().parse();
                                let key = String::from_utf8_lossy(a.key.as_ref()).into_owned();
                                (key, v.unwrap_or(f64::NAN))
                            })
                            .collect();
                        let given: Vec<(&str, f64)> =
                            given.iter().map(|(k, v)| (k.as_str(), *v)).collect();
                        let name = preset_of(&given).map_or_else(|| id.clone(), String::from);
                        // Every keyframe must be the same preset; else the id.
                        match labels.get_mut(id) {
                            None => {
                                labels.insert(id.clone(), vec![name]);
                            }
                            Some(l) if l[0] != name => l[0] = id.clone(),
                            Some(_) => {}
                        }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_are_carla_presets_or_the_id() {
        let xml = r#"<weathers>
          <case weather_id="1"><weather route_percentage="0" cloudiness="5.0" precipitation="0.0"
            wetness="0.0" sun_altitude_angle="15.0" fog_density="2.0"/>
            <weather route_percentage="100" cloudiness="5.0" precipitation="0.0"
            wetness="0.0" sun_altitude_angle="15.0" fog_density="2.0"/></case>
          <case weather_id="2"><weather cloudiness="20" precipitation="30" wetness="0"
            sun_altitude_angle="45" fog_density="3"/></case>
          <case weather_id="10"><weather cloudiness="40" precipitation="100"
            sun_altitude_angle="0" fog_density="7"/></case>
          <case weather_id="7"><weather cloudiness="5" sun_altitude_angle="45" fog_density="2"/>
            <weather cloudiness="100" sun_altitude_angle="45" fog_density="2"/></case>
        </weathers>"#;
        let m = parse(xml, "w.xml").unwrap();
        assert_eq!(m["1"], ["ClearSunset"]);
        assert_eq!(m["2"], ["SoftRainNoon"]);
        assert_eq!(m["10"], ["10"], "altitude 0 is no preset");
        assert_eq!(m["7"], ["7"], "keyframes of two weathers");
        assert!(parse("<weathers/>", "w.xml").is_err());
    }
}
