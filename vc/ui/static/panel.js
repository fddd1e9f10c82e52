// The operator page of vc serve --ui: builds the machine control panel the server describes
// ("hello"), shows the snapshots ("update") and sends the operator's commands over one WebSocket.
"use strict";

const token = new URLSearchParams(location.search).get("token");
let socket = null;
let nextId = 1;
let watched = [];  // the names typed into the watch table, in order
let panelValues = {};
let shownStates = "", shownAlarms = "";
const pending = {};

function $(id) { return document.getElementById(id); }
function element(tag, properties, children) {
  const node = document.createElement(tag);
  Object.assign(node, properties || {});
  for (const child of children || []) node.append(child);
  return node;
}
function say(text, refused) {
  const item = element("li", {textContent: `${new Date().toLocaleTimeString()}  ${text}`,
                               className: refused ? "refused" : ""});
  $("messages").prepend(item);
  while ($("messages").children.length > 100) $("messages").lastChild.remove();
}
function send(command, args, what) {
  if (!socket || socket.readyState !== WebSocket.OPEN) { say(`not connected: ${what || command} not sent`, true); return; }
  const id = nextId++;
  pending[id] = what || command;
  socket.send(JSON.stringify({id: id, command: command, arguments: args || {}}));
}

function connect() {
  const query = token ? `?token=${encodeURIComponent(token)}` : "";
  socket = new WebSocket(`${location.protocol === "https:" ? "wss" : "ws"}://${location.host}/ws${query}`);
  socket.onopen = () => { $("connection").textContent = "connected"; $("connection").className = "ok";
                          if (watched.length) sendWatch(); };
  socket.onclose = () => { $("connection").textContent = "disconnected: reconnecting"; $("connection").className = "bad";
                           setTimeout(connect, 1000); };
  socket.onmessage = (event) => {
    const message = JSON.parse(event.data);
    if (message.hello) build(message.hello);
    else if (message.update) show(message.update);
    else if ("reply" in message) {
      const what = pending[message.reply]; delete pending[message.reply];
      if (!message.done || what !== "key") say(message.message, !message.done);
    }
  };
}

// ---------------------------------------------------------------- the machine control panel
function build(hello) {
  $("machine").textContent = hello.machine;
  const controls = $("controls");
  controls.replaceChildren();
  const groups = {};
  for (const control of hello.controls) {
    if (!groups[control.group]) {
      groups[control.group] = element("div", {className: "group"}, [element("span", {textContent: control.group})]);
      controls.append(groups[control.group]);
    }
    groups[control.group].append(makeControl(control));
  }
  $("lamps").replaceChildren(...hello.lamps.map((name) =>
    element("span", {className: "lamp", id: `lamp-${name}`, textContent: name.replace(/^Lamp\./, "")})));
  $("modes").replaceChildren(element("span", {id: "mode"}),
    ...hello.channels.map((name) => element("span", {id: `channel-${name}`, className: "channel"})));
  $("mda-channel").replaceChildren(...hello.channels.map((name) => element("option", {value: name, textContent: name})));
  const body = $("axes").tBodies[0];
  body.replaceChildren(...hello.axes.map((name) => element("tr", {id: `axis-${name}`},
    ["name", "position", "velocity", "following_error", "referenced"].map((cell) =>
      element("td", {className: cell === "name" || cell === "referenced" ? cell : `number ${cell}`,
                     textContent: cell === "name" ? name : ""})))));
}

function makeControl(control) {
  const id = `key-${control.name}`;
  if (control.kind === "knob") {
    const input = element("input", {type: "range", min: 0, max: control.maximum, step: 1, id: id});
    const shown = element("output", {id: `${id}-value`});
    input.addEventListener("change", () => send("key", {name: control.name, value: Number(input.value)}, "key"));
    input.addEventListener("input", () => { shown.textContent = input.value; });
    return element("label", {className: "knob"}, [`${control.label} `, input, shown]);
  }
  const button = element("button", {id: id, type: "button", textContent: control.label,
                                     className: control.name === "EStop.chainOk" ? "switch estop" : control.kind});
  button.dataset.name = control.name;
  if (control.kind === "key") {
    let held = false;
    const release = () => { if (held) { held = false; send("key", {name: control.name, value: 0}, "key"); } };
    button.addEventListener("pointerdown", (event) => {
      event.preventDefault(); held = true; send("key", {name: control.name, value: 1}, "key"); });
    button.addEventListener("pointerup", release);
    button.addEventListener("pointerleave", release);
  } else {  // a switch: toggles; the emergency-stop button opens the (normally closed) chain while pressed in
    button.addEventListener("click", () => {
      const now = panelValues[control.name] ? 1 : 0;
      send("key", {name: control.name, value: 1 - now}, "switch");
    });
  }
  return button;
}

// ---------------------------------------------------------------- the snapshots
function format(value, digits) { return value === null || value === undefined ? "–" : Number(value).toFixed(digits); }

function show(update) {
  $("clock").textContent = `t = ${update.time_s.toFixed(3)} s`;
  panelValues = update.panel;
  for (const [name, value] of Object.entries(update.panel)) {
    const control = document.getElementById(`key-${name}`);
    if (control && control.tagName === "BUTTON") {
      const lit = name === "EStop.chainOk" ? !value : Boolean(value);
      control.classList.toggle("on", lit);
    } else if (control && control.tagName === "INPUT" && document.activeElement !== control) {
      control.value = value; $(`key-${name}-value`).textContent = value;
    }
    const lamp = document.getElementById(`lamp-${name}`);
    if (lamp) lamp.classList.toggle("on", Boolean(value));
  }
  if (update.connection) showConnection(update.connection);
  if (update.recording) showRecording(update.recording);
  scopeTake(update.scope);
  for (const axis of update.axes) {
    const row = document.getElementById(`axis-${axis.name}`);
    if (!row) continue;
    row.querySelector(".position").textContent = format(axis.position, 3);
    row.querySelector(".velocity").textContent = format(axis.velocity, 1);
    row.querySelector(".following_error").textContent = format(axis.following_error, 4);
    row.querySelector(".referenced").textContent = axis.referenced ? "yes" : "no";
  }
  const states = {};
  for (const [machine, instance, state] of update.states) states[`${machine}/${instance}`] = state;
  $("mode").textContent = `mode ${states["mode_group/MODEGROUP"] || "?"}`;
  for (const option of $("mda-channel").options) {
    const channel = option.value;
    $(`channel-${channel}`).textContent =
      `${channel}: ${states[`channel/${channel}`] || "?"}, program ${states[`program/${channel}`] || "?"}`;
  }
  // the tables are built anew only when they change (a row a person reads or selects stays put)
  const statesText = JSON.stringify(update.states), alarmsText = JSON.stringify(update.alarms);
  if (statesText !== shownStates) {
    shownStates = statesText;
    $("states").tBodies[0].replaceChildren(...update.states.map((row) =>
      element("tr", {}, row.map((cell) => element("td", {textContent: cell})))));
  }
  if (alarmsText === shownAlarms) return showWatch(update);
  shownAlarms = alarmsText;
  $("alarms").tBodies[0].replaceChildren(...update.alarms.map((alarm) => {
    const row = element("tr", {id: `alarm-${alarm.number}`}, [
      element("td", {className: "number", textContent: alarm.number}), element("td", {textContent: alarm.text}),
      element("td", {textContent: [alarm.channel, alarm.axis].filter(Boolean).join(" ")}),
      element("td", {textContent: alarm.clear})]);
    return row;
  }));
  showWatch(update);
}

function showWatch(update) {
  for (const row of $("watch-table").tBodies[0].rows) {
    const entry = update.watch[row.dataset.name];
    if (!entry) continue;
    row.cells[1].textContent = entry.symbol;
    row.cells[2].textContent = entry.address;
    const value = row.cells[3];
    value.textContent = entry.value === null ? "–" : entry.value;
    value.classList.toggle("bit1", entry.value === 1);
    row.classList.toggle("forced", entry.forced);
    row.cells[5].querySelector(".release").disabled = !entry.forced;
    row.cells[3].title = entry.forced ? "forced" : "";
    row.querySelector(".forced-mark").textContent = entry.forced ? " F" : "";
  }
}

function showConnection(connection) {
  $("plc-link").textContent = connection.link;
  $("plc-mode").textContent = connection.mode;
  $("plc-session").textContent = connection.session === null ? "–" : connection.session;
  $("plc-peer").textContent = connection.peer;
  $("plc-life").textContent = connection.sign_of_life;
  $("plc-life").classList.toggle("lost", connection.sign_of_life_lost !== null);
  $("plc-overruns").textContent = connection.overruns === null ? "– (lockstep: no schedule to overrun)"
    : `${connection.overruns} of ${connection.cycles} cycles (${connection.link_overruns} while serving the links)`;
  $("plc-overruns").title = connection.pacing;
}

function showRecording(recording) {
  const text = {none: `not recording: ${recording.note}`,
                recording: `recording to ${recording.path} (cycle ${recording.cycle})`,
                "size limit": `the recording ${recording.path} stopped at its size limit (--record-limit)`,
                ended: `the recording ${recording.path} has ended at cycle ${recording.cycle}`}[recording.state];
  $("record-state").textContent = text;
  $("record-stop").disabled = recording.state === "none" || recording.state === "ended";
  const link = $("record-scenario");
  link.hidden = recording.state !== "ended";
  link.href = `/recording/scenario.yaml${token ? `?token=${encodeURIComponent(token)}` : ""}`;
}

// ---------------------------------------------------------------- watch and force, MDA, alarms
function sendWatch() { send("watch", {names: watched}, "watch"); }

function addWatch(name) {
  if (!name || watched.includes(name)) return;
  watched.push(name);
  const value = element("input", {className: "force-value", size: 6, value: "1"});
  const force = element("button", {className: "force", type: "button", textContent: "force"});
  const release = element("button", {className: "release", type: "button", textContent: "release", disabled: true});
  const remove = element("button", {className: "remove", type: "button", textContent: "×", title: "remove from the table"});
  const row = element("tr", {}, [element("td", {}, [name, element("b", {className: "forced-mark"})]),
    element("td"), element("td"), element("td", {className: "value"}), element("td", {}, [value, force]),
    element("td", {}, [release, remove])]);
  row.dataset.name = name;
  force.addEventListener("click", () => send("force", {name: name, value: Number(value.value)}, "force"));
  release.addEventListener("click", () => send("release", {name: name}, "release"));
  remove.addEventListener("click", () => { watched = watched.filter((item) => item !== name); row.remove(); sendWatch(); });
  $("watch-table").tBodies[0].append(row);
  sendWatch();
}

window.addEventListener("DOMContentLoaded", () => {
  $("watch-add").addEventListener("submit", (event) => {
    event.preventDefault(); addWatch($("watch-name").value.trim()); $("watch-name").value = ""; });
  $("mda-load").addEventListener("click", () =>
    send("mda", {channel: $("mda-channel").value, text: $("mda-text").value}, "mda"));
  $("acknowledge").addEventListener("click", () => send("acknowledge", {}, "acknowledge"));
  $("record-stop").addEventListener("click", () => send("record", {action: "stop"}, "record"));
  connect();
});
