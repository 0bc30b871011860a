// A job page's episode videos: the steps' marks drawn over the playing video (click points, drag paths,
// typed text, the step's number), the step on screen highlighted, and a click on a step seeks to it.
// The marks come from the page itself (a JSON script element): nothing is fetched, so it works from file://.
(function () {
  "use strict";
  const SVG = "http://www.w3.org/2000/svg";

  function svg(name, attrs) {
    const node = document.createElementNS(SVG, name);
    for (const [key, value] of Object.entries(attrs)) node.setAttribute(key, String(value));
    return node;
  }

  function markAt(marks, t) {
    let found = null;
    for (const mark of marks) {
      if (mark.start_s <= t && t < mark.end_s) found = mark;
      if (mark.start_s > t) break;
    }
    return found;
  }

  function draw(layer, label, mark) {
    layer.replaceChildren();
    label.textContent = "";
    label.hidden = mark === null;
    if (mark === null) return;
    label.textContent = mark.text ? mark.label + " · " + mark.text : mark.label;
    label.classList.toggle("failed", !mark.ok);
    if (mark.point) {
      const [x, y] = mark.point;
      layer.append(svg("circle", { class: "click", cx: x, cy: y, r: 16 }), svg("circle", { class: "click-dot", cx: x, cy: y, r: 4 }));
    } else if (mark.path) {
      const [x1, y1, x2, y2] = mark.path;
      const kind = mark.snapped === true ? "snapped" : mark.snapped === false ? "loose" : "unknown";
      const group = svg("g", { class: "drag " + kind });
      group.append(svg("circle", { cx: x1, cy: y1, r: 7 }), svg("line", { x1: x1, y1: y1, x2: x2, y2: y2 }), svg("circle", { cx: x2, cy: y2, r: 10, class: "end" }));
      layer.append(group);
    }
  }

  function setUp(figure) {
    const video = figure.querySelector("video");
    const layer = figure.querySelector("svg.video-marks");
    const label = figure.querySelector(".video-label");
    const marks = JSON.parse(figure.querySelector("script.video-marks-data").textContent);
    const attempt = figure.dataset.attempt;
    const steps = new Map();
    for (const mark of marks) {
      const item = document.getElementById("a" + attempt + "-s" + mark.index);
      if (item === null) continue;
      steps.set(mark.index, item);
      const head = item.querySelector(".step-head");
      head.classList.add("seeks");
      head.title = "show this step in the video (" + mark.start_s.toFixed(1) + " s)";
      head.addEventListener("click", function () {
        video.currentTime = mark.start_s;
        figure.scrollIntoView({ block: "nearest", behavior: "smooth" });
      });
    }
    let shown = undefined;
    function update() {
      const mark = markAt(marks, video.currentTime);
      if (mark === shown) return;
      if (shown && steps.has(shown.index)) steps.get(shown.index).classList.remove("on-screen");
      if (mark && steps.has(mark.index)) steps.get(mark.index).classList.add("on-screen");
      shown = mark;
      draw(layer, label, mark);
    }
    function tick() {
      update();
      if (!video.paused && !video.ended) requestAnimationFrame(tick);
    }
    video.addEventListener("play", function () { requestAnimationFrame(tick); });
    for (const event of ["seeked", "timeupdate", "loadedmetadata"]) video.addEventListener(event, update);
    update();
  }

  document.querySelectorAll("figure.video").forEach(setUp);
})();
