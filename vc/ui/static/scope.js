// The live scope of the operator page: the server samples the picked lanes once per IPO cycle and
// sends what is new with every snapshot ("scope"); this draws the last N seconds as a timing diagram
// in the manual's style (a digital lane as 0/1 steps, an analog lane as a line), triggers on an edge
// of a digital lane, freezes, and saves the canvas as PNG (the VCD comes from the server).
"use strict";

const scope = {lanes: [], samples: [], ipo: 0.002, seconds: 10, frozen: false, trigger: -1, edge: "rising",
               triggeredAt: null};
const DIGITAL_HEIGHT = 34, ANALOG_HEIGHT = 90, LABEL_WIDTH = 190, AXIS_HEIGHT = 22;

function scopeApply() {
  const names = $("scope-lanes").value.split(",").map((name) => name.trim()).filter(Boolean);
  send("scope", {names: names, seconds: Number($("scope-seconds").value)}, "scope");
}

function scopeReset(lanes) {
  scope.lanes = lanes; scope.samples = []; scope.triggeredAt = null; scope.frozen = false;
  const trigger = $("scope-trigger");
  const before = trigger.value;
  trigger.replaceChildren(element("option", {value: "-1", textContent: "no trigger"}),
    ...lanes.map((lane, index) => lane.digital ? element("option", {value: String(index), textContent: lane.name}) : null)
      .filter(Boolean));
  trigger.value = [...trigger.options].some((option) => option.value === before) ? before : "-1";
  scope.trigger = Number(trigger.value);
  scopeStatus();
}

function scopeStatus() {
  let text;
  if (!scope.lanes.length) text = "no lanes: pick signals and axis quantities, then show";
  else if (scope.frozen && scope.triggeredAt !== null)
    text = `triggered at t = ${(scope.triggeredAt * scope.ipo).toFixed(3)} s (${scope.lanes[scope.trigger].name} ${scope.edge}): frozen`;
  else if (scope.frozen) text = "frozen";
  else if (scope.trigger >= 0) text = `armed: waiting for ${scope.lanes[scope.trigger].name} ${scope.edge}`;
  else text = "running";
  $("scope-status").textContent = text;
  $("scope-freeze").textContent = scope.frozen ? "run" : "freeze";
}

function scopeTake(data) {
  if (!data) { if (scope.lanes.length) scopeReset([]); return; }
  if (JSON.stringify(data.lanes) !== JSON.stringify(scope.lanes)) scopeReset(data.lanes);
  scope.ipo = data.ipo_s; scope.seconds = data.seconds;
  if (scope.frozen) return;
  const span = Math.round(scope.seconds / scope.ipo);
  for (const sample of data.samples) {
    const last = scope.samples[scope.samples.length - 1];
    if (scope.trigger >= 0 && scope.triggeredAt === null && last) {
      const before = last[scope.trigger + 1], after = sample[scope.trigger + 1];
      const rose = !before && after, fell = before && !after;
      if ((scope.edge === "rising" && rose) || (scope.edge === "falling" && fell)) scope.triggeredAt = sample[0];
    }
    scope.samples.push(sample);
  }
  const latest = scope.samples.length ? scope.samples[scope.samples.length - 1][0] : 0;
  const keep = latest - span;
  let drop = 0;
  while (drop < scope.samples.length && scope.samples[drop][0] < keep) drop++;
  if (drop) scope.samples.splice(0, drop);
  if (scope.triggeredAt !== null && latest >= scope.triggeredAt + 0.8 * span) scope.frozen = true;
  scopeDraw();
  scopeStatus();
}

function scopeRange() {
  const span = Math.round(scope.seconds / scope.ipo);
  const latest = scope.samples.length ? scope.samples[scope.samples.length - 1][0] : 0;
  const end = scope.frozen && scope.triggeredAt !== null ? scope.triggeredAt + Math.round(0.8 * span) : latest;
  return [end - span, end];
}

// what the diagram shows now, per lane its [cycle, value] pairs (read by the browser tests too)
function scopeShown() {
  const [start, end] = scopeRange();
  const inside = scope.samples.filter((sample) => sample[0] >= start && sample[0] <= end);
  return {lanes: scope.lanes.map((lane, index) => ({name: lane.name, digital: lane.digital,
    values: inside.map((sample) => [sample[0], sample[index + 1]])})), triggeredAt: scope.triggeredAt,
    frozen: scope.frozen};
}

function scopeDraw() {
  const canvas = $("scope-canvas");
  const heights = scope.lanes.map((lane) => lane.digital ? DIGITAL_HEIGHT : ANALOG_HEIGHT);
  canvas.height = Math.max(60, heights.reduce((sum, height) => sum + height, 0) + AXIS_HEIGHT);
  const context = canvas.getContext("2d");
  const width = canvas.width, plot = width - LABEL_WIDTH - 10;
  context.fillStyle = "#fff"; context.fillRect(0, 0, width, canvas.height);
  const [start, end] = scopeRange();
  const x = (cycle) => LABEL_WIDTH + (cycle - start) / Math.max(1, end - start) * plot;
  const shown = scopeShown();
  let top = 0;
  context.font = "12px sans-serif";
  shown.lanes.forEach((lane, index) => {
    const height = heights[index];
    context.strokeStyle = "#d4d8dc"; context.strokeRect(LABEL_WIDTH, top, plot, height);
    context.fillStyle = "#111"; context.fillText(lane.name, 4, top + 14);
    const values = lane.values.filter((pair) => pair[1] !== null);
    let low = 0, high = 1;
    if (!lane.digital && values.length) {
      low = Math.min(...values.map((pair) => pair[1])); high = Math.max(...values.map((pair) => pair[1]));
      if (high === low) { high += 1; low -= 1; }
      context.fillStyle = "#555";
      context.fillText(`${high.toPrecision(6)}`, 4, top + 30); context.fillText(`${low.toPrecision(6)}`, 4, top + height - 4);
    }
    const y = (value) => top + height - 5 - (value - low) / (high - low) * (height - 10);
    context.strokeStyle = lane.digital ? "#2e7d32" : "#1b3a57"; context.lineWidth = 1.5;
    context.beginPath();
    values.forEach((pair, at) => {
      const value = lane.digital ? (pair[1] ? 1 : 0) : pair[1];
      if (at === 0) context.moveTo(x(pair[0]), y(value));
      else if (lane.digital) { context.lineTo(x(pair[0]), y(values[at - 1][1] ? 1 : 0)); context.lineTo(x(pair[0]), y(value)); }
      else context.lineTo(x(pair[0]), y(value));
    });
    context.stroke();
    top += height;
  });
  context.fillStyle = "#555";
  for (let tick = 0; tick <= 5; tick++) {
    const cycle = start + (end - start) * tick / 5;
    context.fillText(`${(cycle * scope.ipo).toFixed(2)} s`, LABEL_WIDTH + plot * tick / 5 - (tick === 5 ? 50 : 0), top + 15);
  }
  if (scope.triggeredAt !== null && scope.triggeredAt >= start) {
    context.strokeStyle = "#b71c1c"; context.setLineDash([4, 3]);
    context.beginPath(); context.moveTo(x(scope.triggeredAt), 0); context.lineTo(x(scope.triggeredAt), top); context.stroke();
    context.setLineDash([]);
  }
}

window.addEventListener("DOMContentLoaded", () => {
  $("scope-apply").addEventListener("click", scopeApply);
  $("scope-trigger").addEventListener("change", () => {
    scope.trigger = Number($("scope-trigger").value); scope.triggeredAt = null; scopeStatus(); });
  $("scope-edge").addEventListener("change", () => { scope.edge = $("scope-edge").value; scope.triggeredAt = null; scopeStatus(); });
  $("scope-freeze").addEventListener("click", () => {
    scope.frozen = !scope.frozen;
    if (!scope.frozen) scope.triggeredAt = null;  // run again: re-armed
    scopeStatus();
  });
  $("scope-png").addEventListener("click", () => { $("scope-png").href = $("scope-canvas").toDataURL("image/png"); });
  $("scope-vcd").href = `/scope.vcd${token ? `?token=${encodeURIComponent(token)}` : ""}`;
});
