//! Measurements of the editor through the real crossterm backend: bytes sent after one
//! fine-step key press (versus a full redraw), the time to the first frame, and how long a
//! frame takes. Printed for the benchmark record; the assertions hold the targets loosely so
//! a busy machine does not fail them.

use std::io::{self, Write};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use grimace::tui::action::Action;
use grimace::tui::app::{App, Colors};
use grimace::tui::scene::Scene;
use grimace::tui::update::update;
use ratatui::backend::CrosstermBackend;
use ratatui::layout::Rect;
use ratatui::{Terminal, TerminalOptions, Viewport};

/// A writer that counts what goes through it.
#[derive(Clone, Default)]
struct Counter(Arc<Mutex<usize>>);

impl Write for Counter {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        *self.0.lock().unwrap() += buf.len();
        Ok(buf.len())
    }
    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

impl Counter {
    fn take(&self) -> usize {
        std::mem::take(&mut *self.0.lock().unwrap())
    }
}

fn app(cols: u16, rows: u16) -> App {
    let (rig, mesh, table) = grimace::cli::edit::default_face().expect("the built-in face");
    let mut app = App::new(Scene::new(rig, mesh).unwrap(), table, None);
    app.colors = Colors::Ansi16;
    update(&mut app, Action::Resize(cols, rows));
    app
}

fn terminal(counter: &Counter, cols: u16, rows: u16) -> Terminal<CrosstermBackend<Counter>> {
    Terminal::with_options(
        CrosstermBackend::new(counter.clone()),
        TerminalOptions {
            viewport: Viewport::Fixed(Rect::new(0, 0, cols, rows)),
        },
    )
    .unwrap()
}

fn median(mut v: Vec<usize>) -> usize {
    v.sort_unstable();
    v[v.len() / 2]
}

#[test]
fn bytes_per_fine_step_are_a_small_part_of_a_full_redraw() {
    for (cols, rows) in [(80u16, 24u16), (120, 40), (200, 60)] {
        let counter = Counter::default();
        let mut term = terminal(&counter, cols, rows);
        let mut app = app(cols, rows);
        grimace::tui::draw(&mut term, &app).unwrap();
        let full = counter.take();
        // Select the left zygomatic major, then step it up and down.
        let index = app.rig().muscle_index("L_Zygomatic_Major").unwrap();
        update(
            &mut app,
            Action::SelectRow(grimace::tui::app::Row::Muscle(index)),
        );
        grimace::tui::draw(&mut term, &app).unwrap();
        counter.take();
        let mut steps = Vec::new();
        for i in 0..20 {
            let step = if i < 10 { 1 } else { -1 };
            update(&mut app, Action::StepFine(step));
            grimace::tui::draw(&mut term, &app).unwrap();
            steps.push(counter.take());
        }
        // Nothing changed: nothing but the synchronized-update brackets is sent.
        grimace::tui::draw(&mut term, &app).unwrap();
        let idle = counter.take();
        let median = median(steps.clone());
        println!(
            "{cols}x{rows}: full redraw {full} B, fine step median {median} B (min {} max {}), unchanged frame {idle} B",
            steps.iter().min().unwrap(),
            steps.iter().max().unwrap()
        );
        assert!(
            median * 4 < full,
            "a step sends {median} B of a {full} B screen"
        );
        assert!(idle < 64, "an unchanged frame sent {idle} B");
    }
}

#[test]
fn start_to_first_frame_and_frame_time() {
    let start = Instant::now();
    let counter = Counter::default();
    let mut term = terminal(&counter, 200, 60);
    let mut app = app(200, 60);
    grimace::tui::draw(&mut term, &app).unwrap();
    let first = start.elapsed();
    let frames = 200;
    let t = Instant::now();
    for i in 0..frames {
        update(&mut app, Action::StepFine(if i % 2 == 0 { 1 } else { -1 }));
        grimace::tui::draw(&mut term, &app).unwrap();
    }
    let per_frame = t.elapsed() / frames;
    // Moving the selection leaves the face as it is: the viewport reuses its picture.
    let t = Instant::now();
    for i in 0..frames {
        update(
            &mut app,
            if i % 2 == 0 {
                Action::SelectNext
            } else {
                Action::SelectPrev
            },
        );
        grimace::tui::draw(&mut term, &app).unwrap();
    }
    let per_select = t.elapsed() / frames;
    println!(
        "load to first frame {first:?}; at 200x60 per frame: fine step + draw {per_frame:?}, selection move + draw {per_select:?}"
    );
    assert!(
        per_select < per_frame,
        "an unchanged face is not drawn again"
    );
    assert!(first.as_millis() < 2000);
}
