//! KITTI raw ground truth: `tracklet_labels.xml`, a boost-serialization XML archive. Boxes are
//! in the Velodyne frame: `(tx, ty, tz)` is the bottom centre, `rz` the yaw; `h, w, l` are
//! height, width and length.
//!
//! The writer emits the same element structure, order and boost class attributes as KITTI's own
//! files, so KITTI's devkit parsers (C++ boost and Python) read what it writes.

use std::path::Path;

use quick_xml::events::Event;

use crate::error::{DatasetError, read_text, write_bytes};
use crate::numfmt::c_general;

/// One object's track: its box size and one pose per frame from `first_frame` on.
#[derive(Clone, Debug, PartialEq)]
pub struct Tracklet {
    /// KITTI class: `Car`, `Van`, `Truck`, `Pedestrian`, `Person (sitting)`, `Cyclist`, `Tram`,
    /// `Misc`.
    pub object_type: String,
    /// Height (metres, along z).
    pub h: f64,
    /// Width (metres, along the box's y).
    pub w: f64,
    /// Length (metres, along the box's x, the heading).
    pub l: f64,
    /// Frame of the first pose.
    pub first_frame: usize,
    /// One pose per frame: `poses[k]` is frame `first_frame + k`.
    pub poses: Vec<TrackletPose>,
}

impl Tracklet {
    /// The pose in frame `frame`, if the tracklet covers it.
    pub fn pose_at(&self, frame: usize) -> Option<&TrackletPose> {
        self.poses.get(frame.checked_sub(self.first_frame)?)
    }

    /// One past the last frame covered.
    pub fn end_frame(&self) -> usize {
        self.first_frame + self.poses.len()
    }
}

/// A tracklet's box in one frame (KITTI's field names and meanings).
#[allow(missing_docs)] // the names are KITTI's own; see the field groups below
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TrackletPose {
    // Bottom centre of the box in the Velodyne frame (metres) and its rotation (radians; only
    // `rz`, the yaw, is labelled).
    pub tx: f64,
    pub ty: f64,
    pub tz: f64,
    pub rx: f64,
    pub ry: f64,
    pub rz: f64,
    /// 0 unset, 1 interpolated, 2 labelled.
    pub state: i32,
    /// 0 visible, 1 partly occluded, 2 fully occluded, -1 unset.
    pub occlusion: i32,
    pub occlusion_kf: i32,
    /// 0 in image, 1 truncated, 2 out of image, 99 ignore, -1 unset.
    pub truncation: i32,
    pub amt_occlusion: f64,
    pub amt_occlusion_kf: i32,
    pub amt_border_l: f64,
    pub amt_border_r: f64,
    pub amt_border_kf: i32,
}

/// Reads a `tracklet_labels.xml`.
pub fn read_tracklets(path: &Path) -> Result<Vec<Tracklet>, DatasetError> {
    let text = read_text(path)?;
    let root = parse_tree(path, &text)?;
    let tracklets = root.child(path, "tracklets")?;
    tracklets
        .items(path)?
        .iter()
        .map(|item| {
            let poses = item.child(path, "poses")?;
            Ok(Tracklet {
                object_type: item.child(path, "objectType")?.text.clone(),
                h: item.number(path, "h")?,
                w: item.number(path, "w")?,
                l: item.number(path, "l")?,
                first_frame: item.integer(path, "first_frame")?,
                poses: poses
                    .items(path)?
                    .iter()
                    .map(|p| read_pose(path, p))
                    .collect::<Result<_, _>>()?,
            })
        })
        .collect()
}

fn read_pose(path: &Path, p: &Element) -> Result<TrackletPose, DatasetError> {
    Ok(TrackletPose {
        tx: p.number(path, "tx")?,
        ty: p.number(path, "ty")?,
        tz: p.number(path, "tz")?,
        rx: p.number(path, "rx")?,
        ry: p.number(path, "ry")?,
        rz: p.number(path, "rz")?,
        state: p.integer(path, "state")?,
        occlusion: p.integer(path, "occlusion")?,
        occlusion_kf: p.integer(path, "occlusion_kf")?,
        truncation: p.integer(path, "truncation")?,
        amt_occlusion: p.number(path, "amt_occlusion")?,
        amt_occlusion_kf: p.integer(path, "amt_occlusion_kf")?,
        amt_border_l: p.number(path, "amt_border_l")?,
        amt_border_r: p.number(path, "amt_border_r")?,
        amt_border_kf: p.integer(path, "amt_border_kf")?,
    })
}

/// Writes a `tracklet_labels.xml` as KITTI's tools do (boost archive version 9, tabs, class
/// attributes on each class's first object).
pub fn write_tracklets(path: &Path, tracklets: &[Tracklet]) -> Result<(), DatasetError> {
    use std::fmt::Write;
    let mut out = String::from(
        "<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"yes\" ?>\n<!DOCTYPE boost_serialization>\n\
         <boost_serialization signature=\"serialization::archive\" version=\"9\">\n\
         <tracklets class_id=\"0\" tracking_level=\"0\" version=\"0\">\n",
    );
    let _ = write!(
        out,
        "\t<count>{}</count>\n\t<item_version>1</item_version>\n",
        tracklets.len()
    );
    let mut first_pose = true;
    for (i, t) in tracklets.iter().enumerate() {
        out += if i == 0 {
            "\t<item class_id=\"1\" tracking_level=\"0\" version=\"1\">\n"
        } else {
            "\t<item>\n"
        };
        let _ = writeln!(
            out,
            "\t\t<objectType>{}</objectType>",
            quick_xml::escape::escape(t.object_type.as_str())
        );
        let [h, w, l] = [t.h, t.w, t.l].map(float);
        let _ = writeln!(out, "\t\t<h>{h}</h>\n\t\t<w>{w}</w>\n\t\t<l>{l}</l>");
        let _ = writeln!(out, "\t\t<first_frame>{}</first_frame>", t.first_frame);
        out += if i == 0 {
            "\t\t<poses class_id=\"2\" tracking_level=\"0\" version=\"0\">\n"
        } else {
            "\t\t<poses>\n"
        };
        let _ = write!(
            out,
            "\t\t\t<count>{}</count>\n\t\t\t<item_version>2</item_version>\n",
            t.poses.len()
        );
        for p in &t.poses {
            out += if first_pose {
                "\t\t\t<item class_id=\"3\" tracking_level=\"0\" version=\"2\">\n"
            } else {
                "\t\t\t<item>\n"
            };
            first_pose = false;
            let reals = [
                ("tx", p.tx),
                ("ty", p.ty),
                ("tz", p.tz),
                ("rx", p.rx),
                ("ry", p.ry),
                ("rz", p.rz),
            ];
            for (name, v) in reals {
                let _ = writeln!(out, "\t\t\t\t<{name}>{}</{name}>", double(v));
            }
            let _ = writeln!(out, "\t\t\t\t<state>{}</state>", p.state);
            let _ = writeln!(out, "\t\t\t\t<occlusion>{}</occlusion>", p.occlusion);
            let _ = writeln!(
                out,
                "\t\t\t\t<occlusion_kf>{}</occlusion_kf>",
                p.occlusion_kf
            );
            let _ = writeln!(out, "\t\t\t\t<truncation>{}</truncation>", p.truncation);
            let _ = writeln!(
                out,
                "\t\t\t\t<amt_occlusion>{}</amt_occlusion>",
                double(p.amt_occlusion)
            );
            let _ = writeln!(
                out,
                "\t\t\t\t<amt_occlusion_kf>{}</amt_occlusion_kf>",
                p.amt_occlusion_kf
            );
            let _ = writeln!(
                out,
                "\t\t\t\t<amt_border_l>{}</amt_border_l>",
                double(p.amt_border_l)
            );
            let _ = writeln!(
                out,
                "\t\t\t\t<amt_border_r>{}</amt_border_r>",
                double(p.amt_border_r)
            );
            let _ = writeln!(
                out,
                "\t\t\t\t<amt_border_kf>{}</amt_border_kf>",
                p.amt_border_kf
            );
            out += "\t\t\t</item>\n";
        }
        out += "\t\t</poses>\n\t\t<finished>1</finished>\n\t</item>\n";
    }
    out += "</tracklets>\n</boost_serialization>\n\n";
    write_bytes(path, out.as_bytes())
}

/// A C++ `double` as boost's text archive writes it (`%.17g`).
fn double(v: f64) -> String {
    c_general(v, 17)
}

/// A C++ `float` (the devkit stores `h, w, l` as floats) as boost writes it (`%.8g`).
fn float(v: f64) -> String {
    c_general(f64::from(v as f32), 8)
}

/// An XML element: its text and child elements (enough for a boost archive).
#[derive(Debug, Default)]
struct Element {
    name: String,
    text: String,
    children: Vec<Element>,
    /// 1-based line of its start tag.
    line: usize,
}

impl Element {
    fn child(&self, path: &Path, name: &str) -> Result<&Element, DatasetError> {
        self.children
            .iter()
            .find(|c| c.name == name)
            .ok_or_else(|| {
                DatasetError::parse(path, self.line, format!("<{}> has no <{name}>", self.name))
            })
    }

    fn number(&self, path: &Path, name: &str) -> Result<f64, DatasetError> {
        let c = self.child(path, name)?;
        c.text.trim().parse().map_err(|_| {
            DatasetError::parse(
                path,
                c.line,
                format!("<{name}>: {:?} is not a number", c.text),
            )
        })
    }

    fn integer<T: std::str::FromStr>(&self, path: &Path, name: &str) -> Result<T, DatasetError> {
        let c = self.child(path, name)?;
        c.text.trim().parse().map_err(|_| {
            DatasetError::parse(
                path,
                c.line,
                format!("<{name}>: {:?} is not an integer", c.text),
            )
        })
    }

    /// The `<item>` children of a boost collection, checked against its `<count>`.
    fn items(&self, path: &Path) -> Result<Vec<&Element>, DatasetError> {
        let count: usize = self.integer(path, "count")?;
        let items: Vec<&Element> = self.children.iter().filter(|c| c.name == "item").collect();
        if items.len() != count {
            return Err(DatasetError::parse(
                path,
                self.line,
                format!(
                    "<{}> says count {count} but holds {} items",
                    self.name,
                    items.len()
                ),
            ));
        }
        Ok(items)
    }
}

/// Line numbers of increasing byte positions, counted once.
struct LineCounter<'a> {
    text: &'a [u8],
    pos: usize,
    line: usize,
}

impl LineCounter<'_> {
    fn line_at(&mut self, pos: u64) -> usize {
        let pos = (pos as usize).min(self.text.len());
        if pos >= self.pos {
            self.line += self.text[self.pos..pos]
                .iter()
                .filter(|&&b| b == b'\n')
                .count();
        } else {
            self.line = self.text[..pos].iter().filter(|&&b| b == b'\n').count() + 1;
        }
        self.pos = pos;
        self.line
    }
}

/// Parses the document into its root element.
fn parse_tree(path: &Path, text: &str) -> Result<Element, DatasetError> {
    let mut reader = quick_xml::Reader::from_str(text);
    let mut lines = LineCounter {
        text: text.as_bytes(),
        pos: 0,
        line: 1,
    };
    let mut stack: Vec<Element> = Vec::new();
    loop {
        let at = lines.line_at(reader.buffer_position());
        let event = reader.read_event().map_err(|e| {
            DatasetError::parse(
                path,
                lines.line_at(reader.error_position()),
                format!("XML: {e}"),
            )
        })?;
        let name = |q: quick_xml::name::QName| q.as_ref().to_string();
        match event {
            Event::Start(e) => stack.push(Element {
                name: name(e.name()),
                line: at,
                ..Default::default()
            }),
            Event::Empty(e) => {
                let element = Element {
                    name: name(e.name()),
                    line: at,
                    ..Default::default()
                };
                match stack.last_mut() {
                    Some(parent) => parent.children.push(element),
                    None => return Ok(element),
                }
            }
            Event::Text(t) => {
                // Leaf text only: whitespace between child elements is layout.
                if let Some(top) = stack.last_mut().filter(|top| top.children.is_empty()) {
                    top.text.push_str(&t.xml10_content());
                }
            }
            Event::GeneralRef(r) => {
                let entity = r.to_string();
                let resolved =
                    quick_xml::escape::resolve_predefined_entity(&entity).ok_or_else(|| {
                        DatasetError::parse(path, at, format!("XML: unknown entity &{entity};"))
                    })?;
                if let Some(top) = stack.last_mut() {
                    top.text.push_str(resolved);
                }
            }
            Event::End(_) => {
                let mut element = stack.pop().ok_or_else(|| {
                    DatasetError::parse(path, at, "XML: closing tag without opening tag")
                })?;
                element.text = element.text.trim().to_string();
                match stack.last_mut() {
                    Some(parent) => parent.children.push(element),
                    None => return Ok(element),
                }
            }
            Event::Eof => {
                return Err(DatasetError::format(
                    path,
                    "XML ends before its root element is closed",
                ));
            }
            Event::Decl(_)
            | Event::DocType(_)
            | Event::Comment(_)
            | Event::PI(_)
            | Event::CData(_) => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shared_data_dir;

    fn pose(tx: f64, state: i32) -> TrackletPose {
        TrackletPose {
            tx,
            ty: -2.5,
            tz: -1.7,
            rz: 0.3,
            state,
            occlusion: 1,
            truncation: 0,
            amt_border_kf: -1,
            amt_border_r: 1.0,
            ..Default::default()
        }
    }

    #[test]
    fn write_then_read_round_trips() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("tracklet_labels.xml");
        let tracklets = vec![
            Tracklet {
                object_type: "Car".into(),
                h: 1.5,
                w: 1.75,
                l: 4.25,
                first_frame: 3,
                poses: vec![pose(10.0, 2), pose(10.5, 1)],
            },
            Tracklet {
                object_type: "Pedestrian".into(),
                h: 1.75,
                w: 0.5,
                l: 0.75,
                first_frame: 0,
                poses: vec![],
            },
            Tracklet {
                object_type: "Person & Co".into(),
                h: 1.25,
                w: 0.5,
                l: 0.5,
                first_frame: 1,
                poses: vec![pose(-3.125, 2)],
            },
        ];
        write_tracklets(&path, &tracklets).unwrap();
        assert_eq!(read_tracklets(&path).unwrap(), tracklets);
        assert_eq!(tracklets[0].pose_at(4).unwrap().tx, 10.5);
        assert!(tracklets[0].pose_at(2).is_none() && tracklets[0].pose_at(5).is_none());
        assert_eq!(tracklets[0].end_frame(), 5);
        write_tracklets(&path, &[]).unwrap();
        assert!(read_tracklets(&path).unwrap().is_empty());
    }

    #[test]
    fn real_file_is_read_and_written_back_byte_for_byte() {
        let Some(data) =
            shared_data_dir("tracklets::real_file_is_read_and_written_back_byte_for_byte")
        else {
            return;
        };
        let path = data.join(
            "kitti-format-samples/raw/2011_09_26/2011_09_26_drive_0001_sync/tracklet_labels.xml",
        );
        let tracklets = read_tracklets(&path).unwrap();
        assert_eq!(tracklets.len(), 15);
        assert_eq!(tracklets.iter().map(Tracklet::end_frame).max(), Some(108));
        let first = &tracklets[0];
        assert_eq!(
            (
                first.object_type.as_str(),
                first.h,
                first.first_frame,
                first.poses.len()
            ),
            ("Car", 2.1672349, 0, 14)
        );
        assert_eq!(first.poses[0].tx, 25.21251603745626);
        assert_eq!(
            (first.poses[0].state, first.poses[0].amt_border_kf),
            (2, -1)
        );
        let tram = tracklets.iter().find(|t| t.object_type == "Tram").unwrap();
        assert_eq!(tram.poses.len(), 108);
        let dir = tempfile::tempdir().unwrap();
        let copy = dir.path().join("tracklet_labels.xml");
        write_tracklets(&copy, &tracklets).unwrap();
        let (ours, theirs) = (
            std::fs::read_to_string(&copy).unwrap(),
            std::fs::read_to_string(&path).unwrap(),
        );
        if ours != theirs {
            let at = ours.lines().zip(theirs.lines()).position(|(a, b)| a != b);
            panic!("first differing line: {at:?}");
        }
    }

    fn error_of(xml: &str) -> DatasetError {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.xml");
        std::fs::write(&path, xml).unwrap();
        let err = read_tracklets(&path).unwrap_err();
        assert!(err.to_string().contains("bad.xml"), "{err}");
        err
    }

    #[test]
    fn malformed_files_are_typed_errors_with_lines() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("good.xml");
        write_tracklets(
            &path,
            &[Tracklet {
                object_type: "Van".into(),
                h: 2.0,
                w: 2.0,
                l: 5.0,
                first_frame: 0,
                poses: vec![pose(1.0, 1)],
            }],
        )
        .unwrap();
        let good = std::fs::read_to_string(&path).unwrap();

        let err = error_of(&good.replace("<tx>1</tx>", "<tx>one</tx>"));
        assert!(matches!(err, DatasetError::Parse { line: 17, .. }), "{err}");
        let err = error_of(&good.replace("\t\t\t\t<rz>0.29999999999999999</rz>\n", ""));
        assert!(err.to_string().contains("has no <rz>"), "{err}");
        let err = error_of(&good.replace(
            "<count>1</count>\n\t<item_version>1",
            "<count>2</count>\n\t<item_version>1",
        ));
        assert!(err.to_string().contains("count 2 but holds 1"), "{err}");
        assert!(matches!(
            error_of(&good[..good.len() / 2]),
            DatasetError::Format { .. } | DatasetError::Parse { .. }
        ));
        assert!(
            error_of(&good.replace("</h>", "</w>"))
                .to_string()
                .contains("XML")
        );
        assert!(
            error_of("<tracklets><count>x</count></tracklets>")
                .to_string()
                .contains("tracklets")
        );
    }
}
