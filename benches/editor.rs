//! The editor's frame: one fine-step key press (update, incremental deformation, render of
//! the face, the ratatui buffer diff written through the real crossterm backend into a
//! counting writer) at 200x60 and 80x24, a selection move (the face's picture is reused), and
//! a fine move in rig mode at 200x60 (the zone overlay drawn), the same in mirror mode, binding
//! one muscle again against binding the whole rig, start to first frame (load the built-in
//! face, bind the rig, draw once).
//!
//! The landmark picker: a cursor step, a turn, and a pick with its undo (`pick_*`).
//!
//! Run: `cargo bench --bench editor -- --warm-up-time 1 --measurement-time 3`

use std::io::{self, Write};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use criterion::{criterion_group, criterion_main, Criterion};
use grimace::tui::action::Action;
use grimace::tui::action::RigAction;
use grimace::tui::app::{App, ColorMode};
use grimace::tui::face::Face;
use grimace::tui::update::update;
use ratatui::backend::CrosstermBackend;
use ratatui::layout::Rect;
use ratatui::{Terminal, TerminalOptions, Viewport};

/// A writer that only counts bytes, standing in for the terminal.
#[derive(Clone, Default)]
struct Counter(Arc<AtomicUsize>);

impl Write for Counter {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.0.fetch_add(buf.len(), Ordering::Relaxed);
        Ok(buf.len())
    }
    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

fn app(cols: u16, rows: u16) -> App {
    let (rig, mesh, table) = grimace::cli::edit::default_face().expect("the built-in face");
    let mut app = App::new(Face::new(rig, mesh).expect("the rig binds"), table, None);
    app.view.colors = ColorMode::Ansi16;
    update(&mut app, Action::Resize(cols, rows));
    app
}

fn terminal(cols: u16, rows: u16) -> Terminal<CrosstermBackend<Counter>> {
    Terminal::with_options(
        CrosstermBackend::new(Counter::default()),
        TerminalOptions {
            viewport: Viewport::Fixed(Rect::new(0, 0, cols, rows)),
        },
    )
    .expect("a terminal on a counting writer")
}

fn frames(c: &mut Criterion) {
    for (cols, rows) in [(200u16, 60u16), (80, 24)] {
        let mut term = terminal(cols, rows);
        let mut app = app(cols, rows);
        let mut cache = Default::default();
        grimace::tui::draw(&mut term, &app, &mut cache).unwrap();
        let mut flip = 1;
        c.bench_function(&format!("fine_step_frame_{cols}x{rows}"), |b| {
            b.iter(|| {
                flip = -flip;
                update(&mut app, Action::StepFine(flip));
                grimace::tui::draw(&mut term, &app, &mut cache).unwrap();
            })
        });
        let mut down = true;
        c.bench_function(&format!("selection_move_frame_{cols}x{rows}"), |b| {
            b.iter(|| {
                down = !down;
                let action = if down {
                    Action::SelectNext
                } else {
                    Action::SelectPrev
                };
                update(&mut app, action);
                grimace::tui::draw(&mut term, &app, &mut cache).unwrap();
            })
        });
    }
    // Rig mode: a fine move of the selected muscle's attachment (the moved muscle checked
    // and its field bound again, the face deformed with the muscle held, drawn with the zone
    // overlay).
    let mut term = terminal(200, 60);
    let mut rig_app = app(200, 60);
    let mut cache = Default::default();
    update(&mut rig_app, Action::Rig(RigAction::Toggle));
    grimace::tui::draw(&mut term, &rig_app, &mut cache).unwrap();
    let mut flip = 1;
    c.bench_function("rig_move_frame_200x60", |b| {
        b.iter(|| {
            flip = -flip;
            let action = RigAction::Move {
                right: flip,
                up: 0,
                coarse: false,
            };
            update(&mut rig_app, Action::Rig(action));
            grimace::tui::draw(&mut term, &rig_app, &mut cache).unwrap();
        })
    });
    // The same in mirror mode: the partner moves too, two muscles bound again.
    update(&mut rig_app, Action::ToggleMirror);
    c.bench_function("rig_mirror_move_frame_200x60", |b| {
        b.iter(|| {
            flip = -flip;
            let action = RigAction::Move {
                right: flip,
                up: 0,
                coarse: false,
            };
            update(&mut rig_app, Action::Rig(action));
            grimace::tui::draw(&mut term, &rig_app, &mut cache).unwrap();
        })
    });
    // What a rig-mode move binds: the zygomatic alone again, against the whole rig.
    let mut bound = grimace::model::BoundRig::bind(rig_app.rig(), rig_app.doc.face.mesh())
        .expect("the rig binds");
    let kind = rig_app.rig().muscles[0].kind.clone();
    c.bench_function("rebind_one_muscle", |b| {
        b.iter(|| bound.rebind_muscle(0, kind.clone()).expect("rebinds"))
    });
    c.bench_function("bind_whole_rig", |b| {
        b.iter(|| {
            grimace::model::BoundRig::bind(rig_app.rig(), rig_app.doc.face.mesh()).expect("binds")
        })
    });
    c.bench_function("start_to_first_frame_200x60", |b| {
        b.iter(|| {
            let mut term = terminal(200, 60);
            let app = app(200, 60);
            grimace::tui::draw(&mut term, &app, &mut Default::default()).unwrap();
        })
    });
}

/// The landmark picker on the default face at 120x40: a cursor step (snap to the nearest
/// visible vertex), a turn (projection and visibility again), and a pick after the minimal
/// set with its undo (the proposals carried through the warp, twice).
fn picker(c: &mut Criterion) {
    use grimace::tui::pick::{PickAction, PickApp, MINIMAL};
    let mesh = grimace::io::builtin::default_mesh();
    let preset = grimace::io::builtin::landmarks("face")
        .expect("the default face's landmarks")
        .vertices(&mesh);
    let mut app = PickApp::new(
        mesh,
        "face.obj".into(),
        "face.landmarks.ron".into(),
        (120, 40),
        grimace::render::CellMode::Braille,
    );
    let mut flip = 1;
    c.bench_function("pick_cursor_step_120x40", |b| {
        b.iter(|| {
            flip = -flip;
            app.update(PickAction::Move(flip, 0))
        })
    });
    c.bench_function("pick_turn_120x40", |b| {
        b.iter(|| {
            flip = -flip;
            app.update(PickAction::Turn(15.0 * f32::from(flip), 0.0))
        })
    });
    for &l in &MINIMAL {
        app.snapped = Some(preset[l]);
        app.update(PickAction::Confirm);
    }
    c.bench_function("pick_confirm_and_undo_warp", |b| {
        b.iter(|| {
            app.update(PickAction::Confirm);
            app.update(PickAction::Undo)
        })
    });
}

criterion_group!(benches, frames, picker);
criterion_main!(benches);
