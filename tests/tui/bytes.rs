//! Bytes the editor sends through the real crossterm backend after one fine-step key press,
//! versus a full redraw, and after a frame where nothing changed. Byte counts do not depend on
//! the machine's speed, so they are asserted; frame times are measured by
//! `cargo bench --bench editor` instead.

use std::io::{self, Write};
use std::sync::{Arc, Mutex};

use grimace::tui::action::Action;
use grimace::tui::app::{App, ColorMode};
use grimace::tui::face::Face;
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
    let mut app = App::new(Face::new(rig, mesh).unwrap(), table, None);
    app.view.colors = ColorMode::Ansi16;
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
        let mut cache = Default::default();
        grimace::tui::draw(&mut term, &app, &mut cache).unwrap();
        let full = counter.take();
        // Select the left zygomatic major, then step it up and down.
        let index = app.rig().muscle_index("L_Zygomatic_Major").unwrap();
        update(
            &mut app,
            Action::SelectRow(grimace::tui::app::Row::Muscle(index)),
        );
        grimace::tui::draw(&mut term, &app, &mut cache).unwrap();
        counter.take();
        let mut steps = Vec::new();
        for i in 0..20 {
            let step = if i < 10 { 1 } else { -1 };
            update(&mut app, Action::StepFine(step));
            grimace::tui::draw(&mut term, &app, &mut cache).unwrap();
            steps.push(counter.take());
        }
        // Nothing changed: nothing but the synchronized-update brackets is sent.
        grimace::tui::draw(&mut term, &app, &mut cache).unwrap();
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
