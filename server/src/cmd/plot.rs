//! `trackd plot RUN_DIR --out bev.png`: a bird's-eye view of a `trackd run` output folder in
//! the world frame: the ego trajectory, each track's trajectory and last box, the class of
//! each track, and optionally the ground truth's trajectories.

mod ground_truth;
mod render;
mod run_dir;

use std::path::PathBuf;

use anyhow::Context;

/// Flags of `trackd plot`.
#[derive(clap::Args)]
pub struct Args {
    /// What `trackd run --out DIR` wrote (its `tracks.csv` and `ego_poses.txt` are read).
    pub run_dir: PathBuf,
    /// The PNG to write.
    #[arg(long)]
    pub out: PathBuf,
    /// Width and height of the image in pixels.
    #[arg(long, default_value_t = 1600, value_parser = clap::value_parser!(u32).range(300..=8000))]
    pub size: u32,
    /// Also draw the ground truth's trajectories: a simulated drive's `gt_tracks.csv` or a KITTI
    /// tracking `label_02/<seq>.txt` (with `calib/<seq>.txt` where KITTI puts it).
    #[arg(long)]
    pub gt: Option<PathBuf>,
    /// The title above the plot [default: the run folder and what it holds].
    #[arg(long)]
    pub title: Option<String>,
}

/// Runs `trackd plot`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let drive = run_dir::read(&args.run_dir)?;
    let gt = match &args.gt {
        Some(path) => ground_truth::read(path, &drive.ego)?,
        None => Vec::new(),
    };
    let title = args.title.clone().unwrap_or_else(|| {
        format!(
            "{}: {} frames, {} tracks (world frame)",
            args.run_dir.display(),
            drive.ego.len(),
            drive.tracks.len()
        )
    });
    let plot = render::render(
        &render::Scene {
            title: &title,
            drive: &drive,
            gt: &gt,
        },
        args.size,
    )?;
    std::fs::write(&args.out, &plot.png)
        .with_context(|| format!("writing {}", args.out.display()))?;
    tracing::info!(
        "{:.3} m per pixel, {} ground-truth objects",
        plot.view.metres_per_pixel(),
        gt.len()
    );
    println!(
        "wrote {} ({} x {} px, {} KB): {} frames, {} tracks",
        args.out.display(),
        args.size,
        args.size,
        plot.png.len().div_ceil(1024),
        drive.ego.len(),
        drive.tracks.len()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use std::fmt::Write as _;
    use std::path::Path;

    use nalgebra::{Isometry3, Translation3, UnitQuaternion};
    use trackd_dataset::poses::write_poses;

    use super::*;

    /// Frames of the synthetic run.
    const FRAMES: u32 = 20;
    /// The synthetic track's id.
    const TRACK: u64 = 7;

    /// A run folder: the sensor moves 1 m east a frame facing north, and sees one car 10 m
    /// ahead, so in the world the car goes along y = 10 from x = 0 to 19.
    fn synthetic_run(dir: &Path) {
        let north = UnitQuaternion::from_euler_angles(0.0, 0.0, std::f64::consts::FRAC_PI_2);
        let ego: Vec<Isometry3<f64>> = (0..FRAMES)
            .map(|k| Isometry3::from_parts(Translation3::new(f64::from(k), 0.0, 0.0), north))
            .collect();
        write_poses(&dir.join("ego_poses.txt"), &ego).unwrap();
        let mut csv = String::from(crate::cmd::run::TRACKS_HEADER);
        for k in 0..FRAMES {
            write!(csv, "\n{k},{TRACK},10,0,0,4,1.8,1.5,0,1,0,0.9,car").unwrap();
        }
        std::fs::write(dir.join("tracks.csv"), csv + "\n").unwrap();
    }

    /// The decoded PNG: width, height and RGB bytes.
    fn decode(png_bytes: &[u8]) -> (u32, u32, Vec<u8>) {
        let decoder = png::Decoder::new(std::io::Cursor::new(png_bytes));
        let mut reader = decoder.read_info().unwrap();
        let mut rgb = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut rgb).unwrap();
        assert_eq!(info.color_type, png::ColorType::Rgb);
        (info.width, info.height, rgb)
    }

    #[test]
    fn a_track_is_drawn_where_the_poses_put_it() {
        let dir = tempfile::tempdir().unwrap();
        synthetic_run(dir.path());
        let drive = run_dir::read(dir.path()).unwrap();
        let scene = render::Scene {
            title: "synthetic",
            drive: &drive,
            gt: &[],
        };
        let plot = render::render(&scene, 400).unwrap();
        let (width, height, rgb) = decode(&plot.png);
        assert_eq!((width, height), (400, 400));
        let colour = render::track_colour(TRACK);
        let colour = [colour.0, colour.1, colour.2];
        // Whether the track's colour is within a pixel of world point `p` (plotters rounds
        // coordinates its own way).
        let coloured_near = |p: [f64; 2]| {
            let (x, y) = plot.view.pixel(p);
            (-1..=1)
                .flat_map(|dy| (-1..=1).map(move |dx| (x + dx, y + dy)))
                .any(|(x, y)| {
                    let i = 3 * (y as usize * width as usize + x as usize);
                    rgb[i..i + 3] == colour
                })
        };
        for k in 3..16 {
            let p = [f64::from(k) + 0.5, 10.0];
            assert!(coloured_near(p), "track not drawn at {p:?}");
            // Where a pose turned the wrong way would have put it.
            let mirrored = [f64::from(k) + 0.5, -10.0];
            assert!(!coloured_near(mirrored), "track drawn at {mirrored:?}");
        }
    }

    #[test]
    fn bad_input_names_the_file_and_line() {
        let dir = tempfile::tempdir().unwrap();
        let args = |out: &str| Args {
            run_dir: dir.path().to_path_buf(),
            out: dir.path().join(out),
            size: 400,
            gt: None,
            title: None,
        };
        let err = format!("{:#}", run(args("a.png")).unwrap_err());
        assert!(err.contains("ego_poses.txt"), "{err}");

        synthetic_run(dir.path());
        let tracks = dir.path().join("tracks.csv");
        let mut text = std::fs::read_to_string(&tracks).unwrap();
        text.insert_str(
            text.find('\n').unwrap() + 1,
            "0,7,ten,0,0,4,1.8,1.5,0,1,0,0.9,car\n",
        );
        std::fs::write(&tracks, text).unwrap();
        let err = format!("{:#}", run(args("b.png")).unwrap_err());
        assert!(err.contains("tracks.csv:2"), "{err}");

        synthetic_run(dir.path());
        std::fs::write(dir.path().join("ego_poses.txt"), "1 0 0\n").unwrap();
        let err = format!("{:#}", run(args("c.png")).unwrap_err());
        assert!(err.contains("ego_poses.txt:1"), "{err}");
        assert!(!dir.path().join("c.png").exists());

        synthetic_run(dir.path());
        run(args("d.png")).unwrap();
        assert!(dir.path().join("d.png").exists());
    }
}
