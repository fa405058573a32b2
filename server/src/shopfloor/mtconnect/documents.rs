//! The response documents: Devices (`/probe`), Streams (`/current`, `/sample`), Assets and
//! Error, built as [`Element`] trees from the buffer.

use std::collections::HashMap;
use std::sync::Arc;

use super::buffer::{Buffer, Observation, Said};
use super::doc::{Element, Text};
use super::model::{Category, Component, Device};

/// What every header carries.
#[derive(Debug, Clone)]
pub struct Sender {
    /// The host's name.
    pub sender: String,
    /// Changes on every start of the agent: a client that sees another one starts over.
    pub instance_id: u64,
    /// The buffer's capacity (its `bufferSize`).
    pub buffer_size: usize,
}

impl Sender {
    fn header(&self) -> Element {
        Element::one("Header")
            .attr("creationTime", crate::host::now_rfc3339())
            .attr("sender", self.sender.clone())
            .attr("instanceId", self.instance_id)
            .attr("version", super::AGENT_VERSION)
    }
}

/// An error code of the standard's `ErrorCodeEnumType`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorCode {
    NoDevice,
    OutOfRange,
    InvalidUri,
    InvalidRequest,
    Unsupported,
    AssetNotFound,
}

impl ErrorCode {
    pub fn word(self) -> &'static str {
        match self {
            ErrorCode::NoDevice => "NO_DEVICE",
            ErrorCode::OutOfRange => "OUT_OF_RANGE",
            ErrorCode::InvalidUri => "INVALID_URI",
            ErrorCode::InvalidRequest => "INVALID_REQUEST",
            ErrorCode::Unsupported => "UNSUPPORTED",
            ErrorCode::AssetNotFound => "ASSET_NOT_FOUND",
        }
    }
}

pub fn error(sender: &Sender, code: ErrorCode, message: &str) -> Element {
    let header = sender.header().attr("bufferSize", sender.buffer_size as u64);
    Element::one("MTConnectError").child(header).child(
        Element::one("Errors").child(Element::item("Error").attr("errorCode", code.word()).text(message.to_string())),
    )
}

/// How many assets there are room for (every tool offset of every device) and how many there are.
#[derive(Debug, Clone, Copy)]
pub struct AssetCounts {
    pub room: usize,
    pub count: usize,
}

pub fn probe(sender: &Sender, buffer: &Buffer, devices: &[Arc<Device>], assets: AssetCounts) -> Element {
    let header = sender
        .header()
        .attr("deviceModelChangeTime", buffer.model_changed_at.clone())
        .attr("bufferSize", sender.buffer_size as u64)
        .attr("assetBufferSize", assets.room as u64)
        .attr("assetCount", assets.count as u64);
    Element::one("MTConnectDevices")
        .child(header)
        .child(Element::one("Devices").children(devices.iter().map(|d| d.probe.clone())))
}

/// A Streams document of `observations` (in sequence order), with `next` as the header's
/// nextSequence.
pub fn streams<'a>(
    sender: &Sender,
    buffer: &Buffer,
    observations: impl IntoIterator<Item = &'a Observation>,
    next: u64,
) -> Element {
    let header = sender
        .header()
        .attr("bufferSize", sender.buffer_size as u64)
        .attr("nextSequence", next)
        .attr("firstSequence", buffer.first_sequence())
        .attr("lastSequence", buffer.last_sequence())
        .attr("deviceModelChangeTime", buffer.model_changed_at.clone());
    // One DeviceStream per device uuid, in the order first met, and one ComponentStream per
    // componentId (both are unique in a document: `componentId` is an `xs:ID`), although a
    // range may hold observations of several models of one device (rebuilt by a rename, a
    // name taken or freed, other axes): the stream is named as the device is now (its latest
    // model), its components in that model's order, then any only an older model had.
    // Observations keep sequence order within each component.
    struct Grouped<'a> {
        /// The device's model now: the one the agent holds, else the latest one met.
        model: Arc<Device>,
        held: bool,
        /// Per componentId: the component (as its latest model has it) and its observations.
        components: Vec<(&'a Component, Vec<&'a Observation>)>,
        /// Index into `components` by componentId.
        by_id: HashMap<&'a str, usize>,
    }
    let mut devices: Vec<Grouped> = Vec::new();
    let mut by_uuid: HashMap<&str, usize> = HashMap::new();
    for o in observations {
        let at = *by_uuid.entry(o.device.uuid.as_str()).or_insert_with(|| {
            let held = buffer.devices.iter().find(|h| h.model.uuid == o.device.uuid);
            let model = held.map_or_else(|| o.device.clone(), |h| h.model.clone());
            devices.push(Grouped { model, held: held.is_some(), components: Vec::new(), by_id: HashMap::new() });
            devices.len() - 1
        });
        let group = &mut devices[at];
        let component = &o.device.components[o.device.items[o.item].component];
        match group.by_id.get(component.id.as_str()) {
            Some(&i) => group.components[i].1.push(o),
            None => {
                group.by_id.insert(component.id.as_str(), group.components.len());
                group.components.push((component, vec![o]));
            }
        }
        // Observations come in sequence order: a later one's model is the newer one.
        if !group.held {
            group.model = o.device.clone();
        }
    }
    let streams = devices.into_iter().map(|mut group| {
        let model = group.model.clone();
        let rank = |id: &str| model.components.iter().position(|c| c.id == id).unwrap_or(usize::MAX);
        // (A stable sort: components of older models only keep the order they were met in.)
        group.components.sort_by_key(|(c, _)| rank(&c.id));
        let component_streams = group.components.into_iter().map(|(c, list)| {
            let c = model.components.iter().find(|m| m.id == c.id).unwrap_or(c);
            let mut stream = Element::item("ComponentStream")
                .attr("component", c.element)
                .attr("componentId", c.id.clone())
                .attr_opt("name", c.name.clone());
            for (category, container) in
                [(Category::Sample, "Samples"), (Category::Event, "Events"), (Category::Condition, "Condition")]
            {
                let members: Vec<Element> = list
                    .iter()
                    .filter(|o| o.device.items[o.item].category == category)
                    .map(|o| observation(o))
                    .collect();
                if !members.is_empty() {
                    stream.push(Element::one(container).children(members));
                }
            }
            stream
        });
        Element::item("DeviceStream")
            .attr("name", model.name.clone())
            .attr("uuid", model.uuid.clone())
            .children(component_streams)
    });
    Element::one("MTConnectStreams").child(header).child(Element::one("Streams").children(streams))
}

fn observation(o: &Observation) -> Element {
    let item = &o.device.items[o.item];
    let base = |name: &'static str| {
        Element::item(name)
            .attr("dataItemId", item.id.clone())
            .attr("timestamp", o.at.to_string())
            .attr("sequence", o.sequence)
    };
    if item.category == Category::Condition {
        let e = match &o.said {
            // The alarm's code identifies the condition's activation (the reference agent's
            // default), so a Normal with that code clears exactly it.
            Said::Fault(alarm) => base("Fault")
                .attr("type", item.kind)
                .attr("nativeCode", alarm.code.clone())
                .attr("conditionId", alarm.code.clone())
                .text({
                    // The line is the program's it is in (a called one's, named).
                    let program = alarm.program.map(|p| format!("O{p:04} ")).unwrap_or_default();
                    match alarm.n {
                        Some(n) => format!("{} ({program}line {}, N{n})", alarm.message, alarm.line),
                        None => format!("{} ({program}line {})", alarm.message, alarm.line),
                    }
                }),
            Said::Normal(code) => base("Normal")
                .attr("type", item.kind)
                .attr_opt("nativeCode", code.clone())
                .attr_opt("conditionId", code.clone()),
            Said::Unavailable | Said::Value(_) => base("Unavailable").attr("type", item.kind),
        };
        return e;
    }
    let e = base(item.element).attr_opt("subType", item.sub_type);
    match &o.said {
        Said::Value(text) => e.text(text.clone()),
        _ => e.text(Text::Str("UNAVAILABLE".into())),
    }
}

/// A cutting tool asset from a tool offset.
#[derive(Debug, Clone, PartialEq)]
pub struct Tool {
    /// The controller (the device's uuid) and its offset number.
    pub device: String,
    pub number: u32,
    /// Length and radius geometry plus wear, corner radius: mm.
    pub length: f64,
    pub radius: f64,
    pub corner_radius: f64,
}

impl Tool {
    pub fn asset_id(&self) -> String {
        format!("{}.T{}", self.device, self.number)
    }

    fn element(&self, timestamp: &str) -> Element {
        let measurements = Element::one("Measurements")
            .child(Element::item("FunctionalLength").attr("code", "LF").attr("units", "MILLIMETER").text(self.length))
            .child(
                Element::item("CuttingDiameterMax")
                    .attr("code", "DC")
                    .attr("units", "MILLIMETER")
                    .text(2.0 * self.radius),
            );
        // The corner radius is the cutting item's (the insert's or the edge's).
        let item = Element::item("CuttingItem").attr("indices", "1").child(Element::one("Measurements").child(
            Element::item("CornerRadius").attr("code", "RE").attr("units", "MILLIMETER").text(self.corner_radius),
        ));
        let life = Element::one("CuttingToolLifeCycle")
            .child(Element::one("CutterStatus").child(Element::item("Status").text("AVAILABLE")))
            .child(Element::one("ProgramToolNumber").text(self.number.to_string()))
            .child(measurements)
            .child(Element::one("CuttingItems").attr("count", 1u64).child(item));
        Element::item("CuttingTool")
            .attr("assetId", self.asset_id())
            .attr("deviceUuid", self.device.clone())
            .attr("timestamp", timestamp.to_string())
            .attr("serialNumber", format!("T{}", self.number))
            .attr("toolId", self.number.to_string())
            .child(life)
    }
}

pub fn assets(sender: &Sender, buffer: &Buffer, tools: &[Tool], counts: AssetCounts) -> Element {
    let header = sender
        .header()
        .attr("deviceModelChangeTime", buffer.model_changed_at.clone())
        .attr("assetBufferSize", counts.room as u64)
        .attr("assetCount", counts.count as u64);
    let now = crate::host::now_rfc3339();
    Element::one("MTConnectAssets")
        .child(header)
        .child(Element::one("Assets").children(tools.iter().map(|t| t.element(&now))))
}
