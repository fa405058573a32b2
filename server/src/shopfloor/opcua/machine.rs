//! One hosted controller as a machine of OPC 40501-1: an object of `MachineToolType` under
//! Machinery's `Objects/Machines` folder, browse name the controller's name, with the type's
//! mandatory parts and the optional ones fivex has values for (docs/shopfloor.md, "OPC UA
//! server", lists them and the mappings). fivex's own parts, in `urn:fivex:opcua`: the axes'
//! positions (`Axes/X/ActualPosition`; 40501-1 monitors no axes), the part count and the panel
//! methods (`Panel/CycleStart`, `FeedHold`, `Reset`).
//!
//! [`Shown`] holds a machine's node ids and what it showed last: each round updates only the
//! values that changed, and an alarm that appeared becomes an event.

use std::cell::Cell;
use std::sync::Arc;

use fivex_engine::controller::{Mode, RunState};
use fivex_engine::machine::AxisKind;
use opcua::nodes::{EventNotifier, Method, NodeBase, NodeType, Object};
use opcua::server::address_space::AddressSpace;
use opcua::types::{
    DataValue, DateTime, EUInformation, ExtensionObject, LocalizedText, NodeId, ObjectTypeId, QualifiedName, Range,
    ReferenceTypeId, UAString, VariableTypeId, Variant,
};

use super::instance::{member_id, Planned, Types};
use super::manager::{METHODS, PANEL};
use super::nodesets::{MACHINERY, MACHINE_TOOL};
use crate::host::station::AlarmChange;
use crate::host::stream::AlarmInfo;
use crate::shopfloor::observe::{Entry, Observed};

/// What every machine shares: namespaces, the types' node ids (the specifications' published
/// numeric ids) and the production program states read from the loaded type.
pub struct Model {
    pub fivex: u16,
    machines: NodeId,
    machine_tool_type: NodeId,
    channel_type: NodeId,
    spindle_type: NodeId,
    states: [ProgramState; 5],
}

/// A state of `ProductionProgramStateMachineType`: its node in the type (the `Id` of
/// `CurrentState`) and its `StateNumber`.
#[derive(Debug, Clone, PartialEq)]
struct ProgramState {
    name: &'static str,
    id: NodeId,
    number: u32,
}

const STATE_NAMES: [&str; 5] = ["Initializing", "Running", "Interrupted", "Aborted", "Ended"];

/// The optional members of `MachineToolType` fivex fills (browse paths below the machine).
const MACHINE_OPTIONAL: &[&str] = &["Identification/Model", "Identification/SoftwareRevision", "Notification/Messages"];
/// ... of the channel's `ChannelMonitoringType`.
const CHANNEL_OPTIONAL: &[&str] = &["RapidOverride"];
/// ... of the spindle's `SpindleMonitoringType`: the spindle speed override.
const SPINDLE_OPTIONAL: &[&str] = &["Override"];
const CHANNEL: &str = "Channel1";
const SPINDLE: &str = "Spindle";

impl Model {
    /// Reads the model from the loaded types; None when a nodeset lacks what fivex shows (a
    /// wrong file: they are embedded).
    pub fn read(types: &Types, fivex: u16, machinery: u16, machine_tool: u16) -> Option<Model> {
        let state_machine = NodeId::new(machine_tool, 15u32);
        let states = STATE_NAMES.map(|name| ProgramState { name, id: NodeId::null(), number: 0 });
        let mut model = Model {
            fivex,
            machines: NodeId::new(machinery, 1001u32),
            machine_tool_type: NodeId::new(machine_tool, 13u32),
            channel_type: NodeId::new(machine_tool, 16u32),
            spindle_type: NodeId::new(machine_tool, 22u32),
            states,
        };
        for state in &mut model.states {
            let (id, number) = types.state(&state_machine, state.name)?;
            state.id = id;
            state.number = number;
        }
        let named =
            |id: &NodeId, name: &str| types.find(id).is_some_and(|n| n.as_node().browse_name().name.as_ref() == name);
        let found = named(&model.machines, "Machines")
            && named(&model.machine_tool_type, "MachineToolType")
            && named(&model.channel_type, "ChannelMonitoringType")
            && named(&model.spindle_type, "SpindleMonitoringType");
        found.then_some(model)
    }

    /// The namespace indexes `read` needs, from the server's namespace table.
    pub fn namespaces(table: &opcua::nodes::NamespaceMap) -> Option<(u16, u16)> {
        Some((table.get_index(MACHINERY)?, table.get_index(MACHINE_TOOL)?))
    }

    fn state(&self, observed: &Observed) -> &ProgramState {
        let name = match observed.run_state {
            RunState::Running => "Running",
            RunState::Hold => "Interrupted",
            RunState::Alarm => "Aborted",
            RunState::Idle if observed.program.is_some() => "Ended",
            RunState::Idle => "Initializing",
        };
        self.states.iter().find(|s| s.name == name).unwrap_or(&self.states[0])
    }
}

impl Types<'_> {
    /// The node and `StateNumber` of the state `name` of a state machine type.
    fn state(&self, type_id: &NodeId, name: &str) -> Option<(NodeId, u32)> {
        let space = self.own;
        let state = space
            .find_references(type_id, Some((ReferenceTypeId::HasComponent, false)), &self.tree, Default::default())
            .map(|r| r.target_node.clone())
            .find(|id| space.find(id).is_some_and(|n| n.as_node().browse_name().name.as_ref() == name))?;
        let number = space
            .find_references(&state, Some((ReferenceTypeId::HasProperty, false)), &self.tree, Default::default())
            .filter_map(|r| match space.find(r.target_node) {
                Some(NodeType::Variable(v)) if v.browse_name().name.as_ref() == "StateNumber" => Some(v.value(
                    opcua::types::TimestampsToReturn::Neither,
                    &Default::default(),
                    &Default::default(),
                    0.0,
                )),
                _ => None,
            })
            .find_map(|value| match value.value {
                Some(Variant::UInt32(n)) => Some(n),
                _ => None,
            })?;
        Some((state, number))
    }
}

/// The node ids of the values that change.
struct Values {
    operation_mode: NodeId,
    channel_state: NodeId,
    channel_mode: NodeId,
    feed_override: NodeId,
    rapid_override: NodeId,
    is_rotating: NodeId,
    spindle_override: NodeId,
    program: NodeId,
    state: NodeId,
    state_id: NodeId,
    state_number: NodeId,
    part_count: NodeId,
    axes: Vec<NodeId>,
}

/// A machine as shown.
pub struct Shown {
    pub root: NodeId,
    pub messages: NodeId,
    /// Every node, to delete them with the controller.
    nodes: Vec<NodeId>,
    values: Values,
    /// The entry shown last; `None` before the first values. A cell: a round updates every
    /// machine while the changes it collects borrow their node ids.
    last: Cell<Option<Arc<Entry>>>,
    /// The round that last listed the controller.
    pub seen: u64,
}

impl Shown {
    /// Plans the machine of `entry`; the nodes go into the address space with
    /// [`super::instance::insert`], then [`Shown::finish`].
    pub fn plan(model: &Model, types: &Types, entry: &Entry, out: &mut Vec<Planned>) -> Shown {
        let ns = model.fivex;
        let root = NodeId::new(ns, entry.id.as_str());
        let at = |path: &str| member_id(&root, path);
        let name = |n: &str| QualifiedName::new(ns, n);
        let start = out.len();
        types.plan_object(
            &root,
            name(&entry.name),
            &entry.name,
            &model.machine_tool_type,
            &model.machines,
            ReferenceTypeId::Organizes,
            MACHINE_OPTIONAL,
            out,
        );
        let monitoring = at("Monitoring");
        types.plan_object(
            &at(&format!("Monitoring/{CHANNEL}")),
            name(CHANNEL),
            CHANNEL,
            &model.channel_type,
            &monitoring,
            ReferenceTypeId::HasComponent,
            CHANNEL_OPTIONAL,
            out,
        );
        types.plan_object(
            &at(&format!("Monitoring/{SPINDLE}")),
            name(SPINDLE),
            SPINDLE,
            &model.spindle_type,
            &monitoring,
            ReferenceTypeId::HasComponent,
            SPINDLE_OPTIONAL,
            out,
        );
        // fivex's extensions.
        let part_count = at("Production/PartCount");
        out.push(Planned {
            node: variable(&part_count, name("PartCount"), 0.0),
            parent: at("Production"),
            reference: ReferenceTypeId::HasComponent.into(),
            type_definition: Some(VariableTypeId::BaseDataVariableType.into()),
        });
        let axes_folder = at("Axes");
        out.push(Planned {
            node: Object::new(&axes_folder, name("Axes"), "Axes", EventNotifier::empty()).into(),
            parent: root.clone(),
            reference: ReferenceTypeId::HasComponent.into(),
            type_definition: Some(ObjectTypeId::FolderType.into()),
        });
        let mut axes = Vec::new();
        for axis in &entry.machine.axes {
            let letter = axis.name.to_string();
            let object = at(&format!("Axes/{letter}"));
            out.push(Planned {
                node: Object::new(&object, name(&letter), letter.as_str(), EventNotifier::empty()).into(),
                parent: axes_folder.clone(),
                reference: ReferenceTypeId::Organizes.into(),
                type_definition: Some(ObjectTypeId::BaseObjectType.into()),
            });
            let position = at(&format!("Axes/{letter}/ActualPosition"));
            out.push(Planned {
                node: variable(&position, name("ActualPosition"), 0.0),
                parent: object,
                reference: ReferenceTypeId::HasComponent.into(),
                type_definition: Some(VariableTypeId::AnalogUnitType.into()),
            });
            let units = at(&format!("Axes/{letter}/ActualPosition/EngineeringUnits"));
            out.push(Planned {
                node: property(&units, QualifiedName::new(0, "EngineeringUnits")),
                parent: position.clone(),
                reference: ReferenceTypeId::HasProperty.into(),
                type_definition: Some(VariableTypeId::PropertyType.into()),
            });
            if axis.stroke.is_some() {
                let range = at(&format!("Axes/{letter}/ActualPosition/EURange"));
                out.push(Planned {
                    node: property(&range, QualifiedName::new(0, "EURange")),
                    parent: position.clone(),
                    reference: ReferenceTypeId::HasProperty.into(),
                    type_definition: Some(VariableTypeId::PropertyType.into()),
                });
            }
            axes.push(position);
        }
        let panel = at(PANEL);
        out.push(Planned {
            node: Object::new(&panel, name(PANEL), PANEL, EventNotifier::empty()).into(),
            parent: root.clone(),
            reference: ReferenceTypeId::HasComponent.into(),
            type_definition: Some(ObjectTypeId::BaseObjectType.into()),
        });
        for method in METHODS {
            let id = at(&format!("{PANEL}/{method}"));
            out.push(Planned {
                node: Method::new(&id, name(method), method, true, true).into(),
                parent: panel.clone(),
                reference: ReferenceTypeId::HasComponent.into(),
                type_definition: None,
            });
        }
        let channel = |member: &str| at(&format!("Monitoring/{CHANNEL}/{member}"));
        let values = Values {
            operation_mode: at("Monitoring/MachineTool/OperationMode"),
            channel_state: channel("ChannelState"),
            channel_mode: channel("ChannelMode"),
            feed_override: channel("FeedOverride"),
            rapid_override: channel("RapidOverride"),
            is_rotating: at(&format!("Monitoring/{SPINDLE}/IsRotating")),
            spindle_override: at(&format!("Monitoring/{SPINDLE}/Override")),
            program: at("Production/ActiveProgram/Name"),
            state: at("Production/ActiveProgram/State/CurrentState"),
            state_id: at("Production/ActiveProgram/State/CurrentState/Id"),
            state_number: at("Production/ActiveProgram/State/CurrentState/Number"),
            part_count,
            axes,
        };
        Shown {
            messages: at("Notification/Messages"),
            nodes: out[start..].iter().map(|p| p.node.as_node().node_id().clone()).collect(),
            root,
            values,
            last: Cell::new(None),
            seen: 0,
        }
    }

    /// After the nodes are inserted: the notifiers, and the machine's constant values to set,
    /// once every node this module sets is known to be there (else the nodesets changed under
    /// it: an error naming the node).
    pub fn finish(&self, space: &mut AddressSpace, entry: &Entry) -> Result<Vec<(NodeId, DataValue)>, String> {
        for id in [&self.root, &self.messages] {
            match space.find_mut(id) {
                Some(NodeType::Object(o)) => o.set_event_notifier(EventNotifier::SUBSCRIBE_TO_EVENTS),
                _ => return Err(format!("{id} is not an object")),
            }
        }
        let constants = self.constants(entry);
        let v = &self.values;
        let values = [
            &v.operation_mode,
            &v.channel_state,
            &v.channel_mode,
            &v.feed_override,
            &v.rapid_override,
            &v.is_rotating,
            &v.spindle_override,
            &v.program,
            &v.state,
            &v.state_id,
            &v.state_number,
            &v.part_count,
        ];
        let missing = values
            .into_iter()
            .chain(&v.axes)
            .chain(constants.iter().map(|(id, _)| id))
            .find(|id| !matches!(space.find(*id), Some(NodeType::Variable(_))))
            .cloned();
        match missing {
            Some(missing) => Err(format!("{missing} is not a variable of the machine")),
            None => Ok(constants),
        }
    }

    /// The values that never change while the machine is shown (its identity).
    fn constants(&self, entry: &Entry) -> Vec<(NodeId, DataValue)> {
        let at = |path: &str| member_id(&self.root, path);
        let text = |s: &str| Variant::from(LocalizedText::new("en", s));
        let mut out = vec![
            (at("Identification/Manufacturer"), text("fivex")),
            (at("Identification/Model"), text(&entry.machine.name)),
            (at("Identification/SerialNumber"), Variant::from(entry.id.as_str())),
            (at("Identification/ProductInstanceUri"), Variant::from(format!("urn:fivex:controller:{}", entry.id))),
            (at("Identification/SoftwareRevision"), Variant::from(env!("CARGO_PKG_VERSION"))),
            (at(&format!("Monitoring/{CHANNEL}/Name")), Variant::from(CHANNEL)),
            (at(&format!("Monitoring/{SPINDLE}/Name")), Variant::from(SPINDLE)),
            (at(&format!("Monitoring/{CHANNEL}/FeedOverride/EngineeringUnits")), units(PERCENT)),
            (at(&format!("Monitoring/{CHANNEL}/FeedOverride/EURange")), range(0.0, 200.0)),
            (at(&format!("Monitoring/{CHANNEL}/RapidOverride/EngineeringUnits")), units(PERCENT)),
            (at(&format!("Monitoring/{CHANNEL}/RapidOverride/EURange")), range(0.0, 100.0)),
            (at(&format!("Monitoring/{SPINDLE}/Override/EngineeringUnits")), units(PERCENT)),
            (at(&format!("Monitoring/{SPINDLE}/Override/EURange")), range(50.0, 120.0)),
            (at("Production/ActiveProgram/NumberInList"), Variant::UInt16(0)),
        ];
        for axis in &entry.machine.axes {
            let position = format!("Axes/{}/ActualPosition", axis.name);
            let unit = match axis.kind {
                AxisKind::Linear => MILLIMETRE,
                AxisKind::Rotary => DEGREE,
            };
            out.push((at(&format!("{position}/EngineeringUnits")), units(unit)));
            if let Some([low, high]) = axis.stroke {
                out.push((at(&format!("{position}/EURange")), range(low, high)));
            }
        }
        out.into_iter().map(|(id, value)| (id, DataValue::new_now(value))).collect()
    }

    /// Whether `entry` is still the machine shown (else it is made again: the controller was
    /// renamed, or a parameter change gave it other axes).
    pub fn shows(&self, entry: &Entry) -> bool {
        let last = self.last.take();
        let same = last.as_ref().is_none_or(|last| {
            last.name == entry.name
                && last.machine.name == entry.machine.name
                && last.machine.axes.len() == entry.machine.axes.len()
                && last
                    .machine
                    .axes
                    .iter()
                    .zip(&entry.machine.axes)
                    .all(|(a, b)| a.name == b.name && a.stroke == b.stroke)
        });
        self.last.set(last);
        same
    }

    /// The values of `entry` that differ from the last shown, into `out` (stamped `at`: a
    /// round's values share their instant), and the alarms raised since (none at the first
    /// sight: an event is a change).
    pub fn update<'a>(
        &'a self,
        model: &Model,
        entry: &Arc<Entry>,
        at: DateTime,
        out: &mut Vec<(&'a NodeId, DataValue)>,
        alarms: &mut Vec<AlarmInfo>,
    ) {
        let now = &entry.observed;
        let previous = self.last.replace(Some(entry.clone()));
        let first = previous.is_none();
        let before = previous.as_ref().map_or(now, |p| &p.observed);
        if !first {
            // Every alarm raised since the last round, also one a reset already cleared (the
            // alarm list would not show it).
            alarms.extend(now.alarm_log.since(before.alarm_log.next()).filter_map(|change| match change {
                AlarmChange::Raised(alarm) => Some(alarm.clone()),
                AlarmChange::Cleared => None,
            }));
        }
        let v = &self.values;
        let mut set = |id: &'a NodeId, value: Variant| out.push((id, DataValue::new_at(value, at)));
        if first || before.mode != now.mode {
            set(&v.operation_mode, Variant::Int32(operation_mode(now.mode)));
            set(&v.channel_mode, Variant::Int32(channel_mode(now.mode)));
        }
        if first || before.run_state != now.run_state {
            set(&v.channel_state, Variant::Int32(channel_state(now.run_state)));
        }
        if first || before.feed_override != now.feed_override {
            set(&v.feed_override, Variant::Double(now.feed_override));
        }
        if first || before.rapid_override != now.rapid_override {
            set(&v.rapid_override, Variant::Double(now.rapid_override));
        }
        if first || (before.spindle != 0.0) != (now.spindle != 0.0) {
            set(&v.is_rotating, Variant::Boolean(now.spindle != 0.0));
        }
        if first || before.spindle_override != now.spindle_override {
            set(&v.spindle_override, Variant::Double(now.spindle_override));
        }
        if first || before.program != now.program {
            let name = now.program.map(|n| format!("O{n:04}")).unwrap_or_default();
            set(&v.program, Variant::from(name));
        }
        let state = model.state(now);
        if first || model.state(before) != state {
            set(&v.state, Variant::from(LocalizedText::new("en", state.name)));
            set(&v.state_id, Variant::from(state.id.clone()));
            set(&v.state_number, Variant::UInt32(state.number));
        }
        if first || before.parts != now.parts {
            set(&v.part_count, Variant::Double(now.parts));
        }
        for (i, id) in v.axes.iter().enumerate() {
            let position = now.machine.get(i).copied().unwrap_or(f64::NAN);
            if first || before.machine.get(i) != now.machine.get(i) {
                set(id, Variant::Double(position));
            }
        }
    }

    /// Removes the machine's nodes and the references to them.
    pub fn remove(&self, space: &mut AddressSpace) {
        for id in &self.nodes {
            space.delete(id, true);
        }
    }
}

/// OPC 40501-1 `MachineOperationMode`: Manual 0, Automatic 1 (Setup, AutoWithManualIntervention,
/// Service, Other: no fivex mode is one).
fn operation_mode(mode: Mode) -> i32 {
    match mode {
        Mode::Auto | Mode::Mdi => 1,
        Mode::Jog | Mode::Handle | Mode::Ref | Mode::Inc => 0,
    }
}

/// OPC 40501-1 `ChannelMode`: Automatic 0, MdaMdi 1, JogManual 2, JogIncrement 3, Reference 6.
/// HANDLE (the manual pulse generator) moves axes by hand as JOG does: JogManual, not
/// TeachingHandle, which teaches a program.
fn channel_mode(mode: Mode) -> i32 {
    match mode {
        Mode::Auto => 0,
        Mode::Mdi => 1,
        Mode::Jog | Mode::Handle => 2,
        Mode::Inc => 3,
        Mode::Ref => 6,
    }
}

/// OPC 40501-1 `ChannelState`: Active 0 (a command executes), Interrupted 1 (held: cycle start
/// goes on), Reset 2 (nothing active: idle, or after an alarm, which ends the program; the
/// alarm itself is an event and the program's state `Aborted`).
fn channel_state(state: RunState) -> i32 {
    match state {
        RunState::Running => 0,
        RunState::Hold => 1,
        RunState::Idle | RunState::Alarm => 2,
    }
}

/// UNECE Recommendation 20 codes as OPC UA's `EUInformation` (OPC 10000-8 §5.6.3): the code's
/// characters as one integer.
struct Unit {
    code: &'static [u8],
    symbol: &'static str,
    name: &'static str,
}

const PERCENT: Unit = Unit { code: b"P1", symbol: "%", name: "percent" };
const MILLIMETRE: Unit = Unit { code: b"MMT", symbol: "mm", name: "millimetre" };
const DEGREE: Unit = Unit { code: b"DD", symbol: "°", name: "degree [unit of angle]" };

fn units(unit: Unit) -> Variant {
    let unit_id = unit.code.iter().fold(0i32, |id, &c| (id << 8) | i32::from(c));
    Variant::from(ExtensionObject::from_message(EUInformation {
        namespace_uri: UAString::from("http://www.opcfoundation.org/UA/units/un/cefact"),
        unit_id,
        display_name: LocalizedText::new("", unit.symbol),
        description: LocalizedText::new("en", unit.name),
    }))
}

fn range(low: f64, high: f64) -> Variant {
    Variant::from(ExtensionObject::from_message(Range { low, high }))
}

fn variable(id: &NodeId, browse_name: QualifiedName, value: f64) -> NodeType {
    let name = browse_name.name.to_string();
    opcua::nodes::Variable::new(id, browse_name, name.as_str(), value).into()
}

fn property(id: &NodeId, browse_name: QualifiedName) -> NodeType {
    let name = browse_name.name.to_string();
    let data_type =
        if name == "EURange" { opcua::types::DataTypeId::Range } else { opcua::types::DataTypeId::EUInformation };
    opcua::nodes::Variable::new_data_value(id, browse_name, name.as_str(), data_type, None, None, Variant::Empty).into()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shopfloor::opcua::{instance, nodesets, FIVEX};
    use fivex_engine::machine::{Machine, MachineConfig};
    use opcua::nodes::NamespaceMap;
    use opcua::server::address_space::CoreNamespace;

    fn entry(id: &str, name: &str, preset: &str) -> Entry {
        let machine: Machine = MachineConfig::preset(preset).expect("a preset").into();
        Entry {
            id: id.into(),
            name: name.into(),
            dialect: fivex_engine::Dialect::Fanuc,
            created_at: String::new(),
            machine: Arc::new(machine),
            observed: Observed {
                emergency_stop: false,
                mode: Mode::Auto,
                run_state: RunState::Idle,
                program_stop: None,
                program: None,
                line: 0,
                line_program: None,
                n: None,
                block: None,
                machine: vec![0.0; 5],
                tip: [0.0; 3],
                feed: 0.0,
                feed_override: 100.0,
                rapid_override: 100.0,
                spindle: 0.0,
                spindle_override: 100.0,
                tool: 0,
                parts: 0.0,
                parts_required: 0.0,
                alarms: Vec::new(),
                alarm_log: Default::default(),
                time_s: 0.0,
            },
            lag: Default::default(),
        }
    }

    /// A machine is its type's mandatory members, the optional ones named, fivex's own parts,
    /// and nothing else; removing it leaves no node behind.
    #[test]
    fn a_machine_is_its_mandatory_members_and_what_fivex_fills() {
        let mut namespaces = NamespaceMap::new();
        let mut core = AddressSpace::new();
        core.import_node_set(&CoreNamespace, &mut namespaces);
        let mut own = AddressSpace::new();
        for import in nodesets::imports().unwrap() {
            own.import_node_set(&*import, &mut namespaces);
        }
        let fivex = namespaces.add_namespace(FIVEX);
        own.add_namespace(FIVEX, fivex);
        let (machinery, machine_tool) = Model::namespaces(&namespaces).unwrap();
        let model = Model::read(&instance::Types::new(&own, &core), fivex, machinery, machine_tool).unwrap();
        // OPC 40501-1 ProductionStateMachineType: Initializing 0, Running 1, Ended 2, Interrupted 3,
        // Aborted 4 (STATE_NAMES order: Initializing, Running, Interrupted, Aborted, Ended).
        assert_eq!(model.states.clone().map(|s| s.number), [0, 1, 3, 4, 2]);

        let entry = entry("c1", "cell", "table-ac");
        let mut planned = Vec::new();
        let shown = Shown::plan(&model, &instance::Types::new(&own, &core), &entry, &mut planned);
        instance::insert(&mut own, planned);
        let constants = shown.finish(&mut own, &entry).expect("every node it sets is there");
        assert!(constants.len() > 10);

        let exists = |path: &str| own.node_exists(&member_id(&shown.root, path));
        for mandatory in [
            "Equipment",
            "Identification/Manufacturer",
            "Identification/SerialNumber",
            "Identification/ProductInstanceUri",
            "Monitoring/MachineTool/OperationMode",
            "Notification",
            "Production/ActiveProgram/Name",
            "Production/ActiveProgram/NumberInList",
            "Production/ActiveProgram/State/CurrentState/Id",
            "Monitoring/Channel1/Name",
            "Monitoring/Channel1/FeedOverride/EngineeringUnits",
            "Monitoring/Spindle/IsRotating",
        ] {
            assert!(exists(mandatory), "{mandatory}");
        }
        for optional in [
            "Identification/Model",
            "Notification/Messages",
            "Monitoring/Channel1/RapidOverride",
            "Monitoring/Spindle/Override",
        ] {
            assert!(exists(optional), "{optional}: fivex fills it");
        }
        for absent in ["Identification/Location", "Monitoring/Stacklight", "Components"] {
            assert!(!exists(absent), "{absent}: optional and not filled");
        }
        for axis in ["X", "Y", "Z", "A", "C"] {
            assert!(exists(&format!("Axes/{axis}/ActualPosition/EngineeringUnits")), "{axis}");
        }
        let tree = opcua::nodes::DefaultTypeTree::new();
        let organized = |own: &AddressSpace| {
            own.find_references(
                &model.machines,
                Some((ReferenceTypeId::Organizes, false)),
                &tree,
                opcua::types::BrowseDirection::Forward,
            )
            .any(|r| *r.target_node == shown.root)
        };
        assert!(organized(&own), "organized by Machines");

        shown.remove(&mut own);
        assert!(shown.nodes.iter().all(|id| !own.node_exists(id)), "no node left");
        assert!(!organized(&own), "nor a reference to it");
    }

    #[test]
    fn unit_ids_are_the_unece_codes() {
        let id = |u: Unit| u.code.iter().fold(0i32, |id, &c| (id << 8) | i32::from(c));
        // OPC 10000-8 Annex: percent 20529, millimetre 5066068, degree 17476.
        assert_eq!(id(PERCENT), 20529);
        assert_eq!(id(MILLIMETRE), 5066068);
        assert_eq!(id(DEGREE), 17476);
    }
}
