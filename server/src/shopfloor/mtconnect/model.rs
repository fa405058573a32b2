//! A controller as an MTConnect device: its components and data items (the `/probe` model)
//! and how each data item's value is read from an [`Observed`].
//!
//! ```text
//! Device (uuid = controller id)    AVAILABILITY
//! ├── Axes
//! │   ├── Linear X, Y, Z …          POSITION ACTUAL / COMMANDED (machine coordinates)
//! │   ├── Rotary A, B, C …          ANGLE ACTUAL / COMMANDED; Configuration/Motion: the mechanism
//! │   └── Rotary S (the spindle)   ROTARY_VELOCITY, ROTARY_VELOCITY_OVERRIDE, ROTARY_MODE = SPINDLE
//! └── Controller                    EMERGENCY_STOP, SYSTEM condition (the alarms)
//!     └── Path                      EXECUTION, CONTROLLER_MODE, PROGRAM, BLOCK, LINE_NUMBER,
//!                                   LINE_LABEL, PATH_POSITION, PATH_FEEDRATE, overrides,
//!                                   TOOL_NUMBER, PART_COUNT
//! ```

use std::sync::Arc;

use fivex_engine::controller::{Mode, ProgramStop, RunState};
use fivex_engine::machine::{AxisKind, Hand, Machine, Side};

use super::doc::{Element, Text};
use crate::host::stream::AlarmInfo;
use crate::shopfloor::observe::{Entry, Observed};

/// What a data item reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Category {
    Sample,
    Event,
    Condition,
}

impl Category {
    fn word(self) -> &'static str {
        match self {
            Category::Sample => "SAMPLE",
            Category::Event => "EVENT",
            Category::Condition => "CONDITION",
        }
    }
}

/// Where a data item's value comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Source {
    Availability,
    EmergencyStop,
    Alarms,
    Execution,
    Mode,
    Program,
    Block,
    Line,
    Label,
    PathPosition,
    Feed,
    FeedOverride,
    RapidOverride,
    Tool,
    Parts,
    PartsRequired,
    Spindle,
    SpindleOverride,
    SpindleMode,
    /// The axis with this index, sampled (ACTUAL) or commanded: the same number in fivex,
    /// which has no servo loop between the two.
    Axis(usize),
}

/// A data item's value at one instant.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Text(Text),
    Unavailable,
    /// A condition: the faults in force (none: `Normal`).
    Faults(Vec<AlarmInfo>),
}

/// One data item of a device.
#[derive(Debug, Clone)]
pub struct Item {
    pub id: String,
    pub category: Category,
    /// The MTConnect type (`POSITION`) and its element name in a stream (`Position`).
    pub kind: &'static str,
    pub element: &'static str,
    pub sub_type: Option<&'static str>,
    pub units: Option<&'static str>,
    /// Index into [`Device::components`].
    pub component: usize,
    source: Source,
}

impl Item {
    /// Whether this is the condition of the controller's alarms.
    pub fn is_alarms(&self) -> bool {
        matches!(self.source, Source::Alarms)
    }

    pub fn value(&self, o: &Observed) -> Value {
        let text = |t: Text| Value::Text(t);
        let optional = |t: Option<String>| t.map_or(Value::Unavailable, |s| Value::Text(Text::Str(s)));
        match self.source {
            Source::Availability => text("AVAILABLE".into()),
            Source::EmergencyStop => text(if o.emergency_stop { "TRIGGERED" } else { "ARMED" }.into()),
            Source::Alarms => Value::Faults(o.alarms.clone()),
            Source::Execution => text(execution(o).into()),
            Source::Mode => text(
                match o.mode {
                    Mode::Auto => "AUTOMATIC",
                    Mode::Mdi => "MANUAL_DATA_INPUT",
                    Mode::Jog | Mode::Handle | Mode::Ref | Mode::Inc => "MANUAL",
                }
                .into(),
            ),
            Source::Program => optional(o.program.map(|n| format!("O{n:04}"))),
            Source::Block => optional(o.block.clone().filter(|b| !b.is_empty())),
            Source::Line => text(Text::Num(o.line as f64)),
            Source::Label => optional(o.n.map(|n| format!("N{n}"))),
            Source::PathPosition => text(Text::Vec3(o.tip)),
            // MTConnect's feedrate unit is mm/s.
            Source::Feed => text(Text::Num(o.feed / 60.0)),
            Source::FeedOverride => text(Text::Num(o.feed_override)),
            Source::RapidOverride => text(Text::Num(o.rapid_override)),
            Source::Tool => text(Text::Num(o.tool as f64)),
            Source::Parts => text(Text::Num(o.parts)),
            Source::PartsRequired => text(Text::Num(o.parts_required)),
            Source::Spindle => text(Text::Num(o.spindle)),
            Source::SpindleOverride => text(Text::Num(o.spindle_override)),
            Source::SpindleMode => text("SPINDLE".into()),
            Source::Axis(i) => o.machine.get(i).map_or(Value::Unavailable, |v| text(Text::Num(*v))),
        }
    }
}

/// EXECUTION from the run state: an alarm or the emergency stop stops the program; a program
/// held at a stop of its own is PROGRAM_STOPPED (M00, `#3006`, a single-block stop) or
/// OPTIONAL_STOP (M01), the MTConnect 2.5 values for "a command from the program has
/// intentionally interrupted execution".
fn execution(o: &Observed) -> &'static str {
    if o.emergency_stop {
        return "STOPPED";
    }
    match (o.run_state, o.program_stop) {
        (RunState::Idle, _) => "READY",
        (RunState::Running, _) => "ACTIVE",
        (RunState::Hold, Some(ProgramStop::Optional)) => "OPTIONAL_STOP",
        (RunState::Hold, Some(ProgramStop::Stop | ProgramStop::SingleBlock)) => "PROGRAM_STOPPED",
        (RunState::Hold, None) => "FEED_HOLD",
        (RunState::Alarm, _) => "STOPPED",
    }
}

/// A component of the device: its element (`Linear`), id and name.
#[derive(Debug, Clone)]
pub struct Component {
    pub element: &'static str,
    pub id: String,
    pub name: Option<String>,
}

/// A controller as a device.
#[derive(Debug, Clone)]
pub struct Device {
    /// The controller id, also the device's uuid.
    pub uuid: String,
    pub name: String,
    pub items: Vec<Item>,
    pub components: Vec<Component>,
    /// The `<Device>` element `/probe` shows.
    pub probe: Element,
    /// The machine it was built for: a parameter change replaces it, and the model with it.
    pub machine: Arc<Machine>,
}

impl Device {
    /// The device of `entry`, named `name` (`unique_names`).
    pub fn of(entry: &Entry, name: &str) -> Device {
        Builder::new(entry, name).build()
    }

    /// Whether `name` (a request path's device) names this device: its name or its uuid.
    pub fn is(&self, name: &str) -> bool {
        self.name == name || self.uuid == name
    }
}

/// The device names of `entries` (in creation order): each controller's name, and for a name an
/// earlier controller already has, the name and the head of its id (`Mill-1a2b3c4d`), so that
/// a request's `/{device}` names one device and the probe's names are unique.
pub fn unique_names(entries: &[Arc<Entry>]) -> Vec<String> {
    let mut used = std::collections::HashSet::new();
    entries
        .iter()
        .map(|e| {
            let name = if used.contains(e.name.as_str()) {
                format!("{}-{}", e.name, e.id.get(..8).unwrap_or(&e.id))
            } else {
                e.name.clone()
            };
            used.insert(name.clone());
            name
        })
        .collect()
}

struct Builder<'a> {
    entry: &'a Entry,
    id: String,
    items: Vec<Item>,
    components: Vec<Component>,
    name: &'a str,
}

impl<'a> Builder<'a> {
    fn new(entry: &'a Entry, name: &'a str) -> Builder<'a> {
        // The device's `id` attribute prefixes every id: an XML ID must not start with a digit.
        Builder { entry, id: format!("d{}", entry.id), items: Vec::new(), components: Vec::new(), name }
    }

    fn component(&mut self, element: &'static str, suffix: &str, name: Option<String>) -> usize {
        let id = if suffix.is_empty() { self.id.clone() } else { format!("{}_{suffix}", self.id) };
        self.components.push(Component { element, id, name });
        self.components.len() - 1
    }

    /// Adds a data item to `component`; returns its `<DataItem>`.
    fn item(&mut self, component: usize, suffix: &str, spec: Spec) -> Element {
        let item = Item {
            id: format!("{}_{suffix}", self.id),
            category: spec.category,
            kind: spec.kind,
            element: spec.element,
            sub_type: spec.sub_type,
            units: spec.units,
            component,
            source: spec.source,
        };
        let mut e = Element::item("DataItem")
            .attr("category", item.category.word())
            .attr("id", item.id.clone())
            .attr("type", item.kind)
            .attr_opt("subType", item.sub_type)
            .attr_opt("units", item.units);
        if let Some(native) = spec.native_units {
            e = e.attr("nativeUnits", native);
        }
        if let Some(system) = spec.coordinate_system {
            e = e.attr("coordinateSystem", system);
        }
        if spec.source == Source::SpindleMode {
            e = e.child(Element::one("Constraints").child(Element::item("Value").text("SPINDLE")));
        }
        self.items.push(item);
        e
    }

    fn build(mut self) -> Device {
        let entry = self.entry;
        let machine = &entry.machine;
        let device = self.component("Device", "", None);
        let avail = self.item(device, "avail", Spec::event("AVAILABILITY", "Availability", Source::Availability));

        // Axes, with the mechanism as each axis's Motion.
        let axes = self.component("Axes", "axes", None);
        let mut axis_elements = Vec::new();
        for (i, axis) in machine.axes.iter().enumerate() {
            let letter = axis.name.to_string();
            let (element, kind, stream, units) = match axis.kind {
                AxisKind::Linear => ("Linear", "POSITION", "Position", "MILLIMETER"),
                AxisKind::Rotary => ("Rotary", "ANGLE", "Angle", "DEGREE"),
            };
            let c = self.component(element, &letter, Some(letter.clone()));
            let actual = Spec::sample(kind, stream, Source::Axis(i), units).sub("ACTUAL").system("MACHINE");
            let commanded = Spec::sample(kind, stream, Source::Axis(i), units).sub("COMMANDED").system("MACHINE");
            let items =
                vec![self.item(c, &format!("{letter}act"), actual), self.item(c, &format!("{letter}cmd"), commanded)];
            let mut e = self.component_element(c);
            if let Some(motion) = self.motion(i) {
                e.push(Element::one("Configuration").child(motion));
            }
            axis_elements.push(e.child(Element::one("DataItems").children(items)));
        }
        let spindle = self.component("Rotary", "S", Some("S".into()));
        let spindle_items = vec![
            self.item(
                spindle,
                "Srpm",
                Spec::sample("ROTARY_VELOCITY", "RotaryVelocity", Source::Spindle, "REVOLUTION/MINUTE").sub("ACTUAL"),
            ),
            self.item(
                spindle,
                "Sovr",
                Spec::event("ROTARY_VELOCITY_OVERRIDE", "RotaryVelocityOverride", Source::SpindleOverride)
                    .units("PERCENT"),
            ),
            self.item(spindle, "Smode", Spec::event("ROTARY_MODE", "RotaryMode", Source::SpindleMode)),
        ];
        axis_elements.push(self.component_element(spindle).child(Element::one("DataItems").children(spindle_items)));

        // The controller and its one path.
        let controller = self.component("Controller", "ctrl", None);
        let controller_items = vec![
            self.item(controller, "estop", Spec::event("EMERGENCY_STOP", "EmergencyStop", Source::EmergencyStop)),
            self.item(controller, "system", Spec::condition("SYSTEM", Source::Alarms)),
        ];
        let path = self.component("Path", "path", None);
        let path_items = vec![
            self.item(path, "exec", Spec::event("EXECUTION", "Execution", Source::Execution)),
            self.item(path, "mode", Spec::event("CONTROLLER_MODE", "ControllerMode", Source::Mode)),
            self.item(path, "program", Spec::event("PROGRAM", "Program", Source::Program)),
            self.item(path, "block", Spec::event("BLOCK", "Block", Source::Block)),
            self.item(path, "line", Spec::event("LINE_NUMBER", "LineNumber", Source::Line).sub("ABSOLUTE")),
            self.item(path, "label", Spec::event("LINE_LABEL", "LineLabel", Source::Label)),
            self.item(
                path,
                "pos",
                Spec::sample("PATH_POSITION", "PathPosition", Source::PathPosition, "MILLIMETER_3D")
                    .sub("ACTUAL")
                    .system("WORK"),
            ),
            self.item(
                path,
                "feed",
                Spec::sample("PATH_FEEDRATE", "PathFeedrate", Source::Feed, "MILLIMETER/SECOND")
                    .sub("ACTUAL")
                    .native("MILLIMETER/MINUTE"),
            ),
            self.item(
                path,
                "feedovr",
                Spec::event("PATH_FEEDRATE_OVERRIDE", "PathFeedrateOverride", Source::FeedOverride)
                    .sub("PROGRAMMED")
                    .units("PERCENT"),
            ),
            self.item(
                path,
                "rapidovr",
                Spec::event("PATH_FEEDRATE_OVERRIDE", "PathFeedrateOverride", Source::RapidOverride)
                    .sub("RAPID")
                    .units("PERCENT"),
            ),
            self.item(path, "tool", Spec::event("TOOL_NUMBER", "ToolNumber", Source::Tool)),
            self.item(path, "parts", Spec::event("PART_COUNT", "PartCount", Source::Parts).sub("ALL")),
            self.item(path, "target", Spec::event("PART_COUNT", "PartCount", Source::PartsRequired).sub("TARGET")),
        ];

        let description = Element::one("Description")
            .attr("manufacturer", "fivex")
            .attr("model", machine.name.clone())
            .attr("serialNumber", entry.id.clone())
            .text(format!("virtual {} controller", entry.dialect.name()));
        let coordinate_systems = Element::one("Configuration").child(
            Element::one("CoordinateSystems").child(
                Element::item("CoordinateSystem")
                    .attr("id", format!("{}_machine", self.id))
                    .attr("type", "MACHINE")
                    .attr("name", "machine"),
            ),
        );
        let path_element = self.component_element(path).child(Element::one("DataItems").children(path_items));
        let controller_element = self
            .component_element(controller)
            .child(Element::one("DataItems").children(controller_items))
            .child(Element::one("Components").child(path_element));
        let axes_element = self.component_element(axes).child(Element::one("Components").children(axis_elements));
        let probe = Element::item("Device")
            .attr("id", self.id.clone())
            .attr("name", self.name.to_string())
            .attr("uuid", entry.id.clone())
            .child(description)
            .child(coordinate_systems)
            .child(Element::one("DataItems").child(avail))
            .child(Element::one("Components").child(axes_element).child(controller_element));
        Device {
            uuid: entry.id.clone(),
            name: self.name.to_string(),
            items: self.items,
            components: self.components,
            probe,
            machine: entry.machine.clone(),
        }
    }

    fn component_element(&self, index: usize) -> Element {
        let c = &self.components[index];
        Element::item(c.element).attr("id", c.id.clone()).attr_opt("name", c.name.clone())
    }

    /// The axis's place in the mechanism (MTConnect's Motion): a linear axis slides along its
    /// machine direction; a rotary axis of the chain turns about its direction (left-handed
    /// ones about the reversed one) through its point, riding on the link before it on its side.
    fn motion(&self, axis: usize) -> Option<Element> {
        let machine = &self.entry.machine;
        let a = &machine.axes[axis];
        let system = format!("{}_machine", self.id);
        let motion = |suffix: &str, kind: &str| {
            Element::one("Motion")
                .attr("id", format!("{}_{suffix}_motion", self.id))
                .attr("coordinateSystemIdRef", system.clone())
                .attr("type", kind)
                .attr("actuation", "DIRECT")
        };
        let letter = a.name.to_string();
        if a.kind == AxisKind::Linear {
            let direction = match a.name {
                'X' | 'U' => [1.0, 0.0, 0.0],
                'Y' | 'V' => [0.0, 1.0, 0.0],
                'Z' | 'W' => [0.0, 0.0, 1.0],
                _ => return None,
            };
            return Some(motion(&letter, "PRISMATIC").child(Element::one("Axis").text(Text::Vec3(direction))));
        }
        let links: Vec<_> = machine.rotary.iter().filter(|l| l.fixed.is_none()).collect();
        let at = links.iter().position(|l| l.axis == a.name)?;
        let link = links[at];
        let parent = links[..at].iter().rev().find(|l| l.side == link.side);
        let sign = if link.hand == Hand::Left { -1.0 } else { 1.0 };
        let norm = link.direction.iter().map(|v| v * v).sum::<f64>().sqrt().max(f64::MIN_POSITIVE);
        let direction = link.direction.map(|v| sign * v / norm);
        let description = match link.side {
            Side::Table => "table axis: origin in machine coordinates at zero position",
            Side::Head => "head axis: origin relative to the X/Y/Z carriage reference point",
        };
        let mut e = motion(&letter, "REVOLUTE");
        if let Some(parent) = parent {
            e = e.attr("parentIdRef", format!("{}_{}_motion", self.id, parent.axis));
        }
        Some(
            e.child(Element::one("Description").text(description))
                .child(Element::one("Origin").text(Text::Vec3(link.point)))
                .child(Element::one("Axis").text(Text::Vec3(direction))),
        )
    }
}

/// A data item's definition before it has an id.
struct Spec {
    category: Category,
    kind: &'static str,
    element: &'static str,
    sub_type: Option<&'static str>,
    units: Option<&'static str>,
    native_units: Option<&'static str>,
    coordinate_system: Option<&'static str>,
    source: Source,
}

impl Spec {
    fn new(category: Category, kind: &'static str, element: &'static str, source: Source) -> Spec {
        Spec {
            category,
            kind,
            element,
            sub_type: None,
            units: None,
            native_units: None,
            coordinate_system: None,
            source,
        }
    }

    fn event(kind: &'static str, element: &'static str, source: Source) -> Spec {
        Spec::new(Category::Event, kind, element, source)
    }

    fn sample(kind: &'static str, element: &'static str, source: Source, units: &'static str) -> Spec {
        Spec::new(Category::Sample, kind, element, source).units(units)
    }

    /// A condition: its stream elements are `Normal`, `Warning`, `Fault`, `Unavailable`.
    fn condition(kind: &'static str, source: Source) -> Spec {
        Spec::new(Category::Condition, kind, "", source)
    }

    fn sub(mut self, sub_type: &'static str) -> Spec {
        self.sub_type = Some(sub_type);
        self
    }

    fn units(mut self, units: &'static str) -> Spec {
        self.units = Some(units);
        self
    }

    fn native(mut self, units: &'static str) -> Spec {
        self.native_units = Some(units);
        self
    }

    fn system(mut self, system: &'static str) -> Spec {
        self.coordinate_system = Some(system);
        self
    }
}
