//! Pictures of `rappel online`: the final state of a run (prior and true obstacles, the tether,
//! the path driven) and one picture per timeline event.

use rappel_planners::online::OnlineSession;
use rappel_planners::online::simulate::TimelineEvent;

use crate::{Layer, Picture};

/// The picture of a session: the true map's obstacles as known now, the BTM, the current sleeve
/// and SHP with its anchors, the travelled descent and the selected ascent, start and goal.
pub fn picture(session: &OnlineSession, title: &str) -> String {
    let map = session.btm().map();
    let mut pic = Picture::of_map(&map);
    if let Some(c) = session.class() {
        pic.sleeve(session.btm(), &c.shp.sleeve);
    }
    pic.btm(session.btm());
    pic.map(&map);
    if let Some(c) = session.class() {
        pic.polyline(Layer::Ascent, &c.ascent);
        pic.taut_path(&c.shp.taut);
    }
    pic.polyline(Layer::Descent, session.travelled());
    if session.route().len() > 1 {
        pic.polyline(Layer::Path, session.route());
    }
    pic.marker(Layer::Robot, session.robot());
    pic.start_goal(session.start(), session.goal());
    pic.finish(title)
}

/// The picture after one event (for `--frames`).
pub fn event_picture(event: &TimelineEvent, session: &OnlineSession) -> String {
    let title = format!(
        "step {}: {} -> {:?}",
        event.step,
        event.outcome.case.describe(),
        event.outcome.decision
    );
    picture(session, &title)
}
