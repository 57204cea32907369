//! `apply`: the one place actions change the app. Pure apart from the
//! domain calls the action asks for (a rating is written to the store before
//! `apply` returns), so every key can be tested without a terminal.

use super::action::Action;
use super::app::App;
use super::i18n;
use super::screens::Nav;
use super::stack::Tui;

pub fn apply(app: &mut Tui, action: Action) {
    match action {
        Action::Quit => {
            app.quit = true;
            return;
        }
        Action::ToggleHelp => {
            app.help = !app.help;
            app.help_scroll = 0;
            return;
        }
        Action::CloseHelp => {
            app.help = false;
            return;
        }
        Action::HelpDown => {
            let max = super::view::help_scroll_max(app);
            app.help_scroll = (app.help_scroll + 1).min(max);
            return;
        }
        Action::HelpUp => {
            app.help_scroll = app.help_scroll.saturating_sub(1);
            return;
        }
        Action::Resize(w, h) => {
            app.size = (w, h);
            return;
        }
        Action::ToggleLanguage => {
            toggle_language(app);
            return;
        }
        _ => {}
    }
    let Some(mut top) = app.stack.pop() else {
        return;
    };
    let nav = top.view_mut().apply(app, action);
    app.stack.push(top);
    match nav {
        Nav::Stay => {}
        Nav::Push(screen) => app.push(screen),
        Nav::Pop => {
            app.pop();
            if let Some(said) = app.edit_said.take() {
                app.info(said);
            }
        }
        Nav::Replace(screen) => {
            app.pop();
            app.push(screen);
        }
    }
}

fn toggle_language(app: &mut App) {
    app.lang = i18n::other(&app.lang).to_string();
    if let Err(e) = app.services.save_language(&app.lang) {
        app.error(e);
    }
}
