// The playground's stylesheet, adopted by each widget's shadow root.
//
// Layout follows the widget's own width (container queries), so an embedded
// widget and the full page behave alike: below 900 px the panel becomes a
// drawer over the view and the plots wrap; below 560 px they stack.
export const STYLE = `
:host { display: block; position: relative; font: 13px/1.35 system-ui, sans-serif; color: #1d2330; background: #fafbfc;
        border: 1px solid #dde1e8; border-radius: 6px; overflow: hidden; min-height: 320px; container: sp / inline-size; }
:host([fill]) { border: 0; border-radius: 0; }
* { box-sizing: border-box; }
.sp { display: grid; height: 100%; grid-template-columns: minmax(0, 1fr); grid-template-rows: minmax(0, 1fr) auto;
      position: relative; }
/* Wide: the panel on the right, the plots' strip 36 % of the widget's
   height, within 12.5rem and 15.5rem: room for two legend rows
   and a readable plot. The 3D view takes the rest; its area is also what a
   frame costs the browser where the GPU is emulated (about 38 ns a pixel
   shown, render/mod.rs). */
.sp.full { grid-template-columns: minmax(0, 1fr) 22rem; grid-template-rows: minmax(0, 1fr) clamp(12.5rem, 36%, 15.5rem); }
.stage { position: relative; min-height: 0; min-width: 0; overflow: hidden; }
.view { width: 100%; height: 100%; display: block; touch-action: pan-y; cursor: crosshair; outline: none; }
:host([fill]) .view { touch-action: none; }
.view:focus-visible { outline: 3px solid #2563eb; outline-offset: -3px; }
.stats, .hud { position: absolute; top: 0.5rem; background: rgba(255,255,255,0.9); border: 1px solid #dde1e8; border-radius: 4px;
       font: 12px/1.35 ui-monospace, monospace; white-space: pre-wrap; pointer-events: none; max-width: calc(50% - 0.75rem); }
.stats { left: 0.5rem; padding: 0.2rem 0.45rem; color: #3a4150; }
.hud { right: 0.5rem; padding: 0.25rem 0.5rem; }
.camera-thumb { position: absolute; left: 0.5rem; bottom: 2.8rem; width: 160px; height: 120px; border: 1px solid #dde1e8; border-radius: 4px; background: #000; pointer-events: none; }
.camera-thumb[hidden] { display: none; }
.notices { position: absolute; left: 0.5rem; bottom: 0.5rem; display: grid; grid-template-columns: minmax(0, auto) auto; align-items: start;
           justify-items: start; gap: 0.25rem; max-width: min(34rem, calc(100% - 8rem)); pointer-events: none; }
.notices[data-corner="top-left"] { top: var(--notices-top, 0.5rem); bottom: auto; max-width: min(34rem, calc(50% - 0.75rem)); }
.notices[data-corner="bottom-right"] { left: auto; right: 0.5rem; }
.notices:not(.expanded) .notice ~ .notice { display: none; }
.notices .more { grid-column: 2; grid-row: 1; pointer-events: auto; font-size: 11px; padding: 0.1rem 0.35rem; border-radius: 4px;
                 border: 1px solid #c9ced8; background: #fff; color: #1d2330; cursor: pointer; }
.notice { grid-column: 1; max-width: 100%; background: rgba(29,35,48,0.8); color: #fff; border-radius: 4px; padding: 0.2rem 0.5rem; font-size: 12px;
          display: flex; gap: 0.5rem; align-items: baseline; }
.notice span { flex: 1; min-width: 0; white-space: nowrap; overflow: hidden; text-overflow: ellipsis; }
.notices.expanded .notice span { white-space: normal; }
.notice.pinned { background: rgba(165,39,20,0.85); pointer-events: auto; box-shadow: 0 1px 4px rgba(0,0,0,0.25); }
.notice.lock, .notice.switchRisk, .notice.transitionTooSlow { background: rgba(122,75,0,0.8); }
.notice .dismiss { background: transparent; color: #fff; border: 1px solid rgba(255,255,255,0.6); border-radius: 3px; cursor: pointer; font-size: 12px; line-height: 1; padding: 0.1rem 0.35rem; }
.hint-box { position: absolute; left: 50%; bottom: 0.6rem; transform: translateX(-50%); background: rgba(29,35,48,0.88); color: #fff;
            border-radius: 4px; padding: 0.25rem 0.6rem; font-size: 12px; pointer-events: none; white-space: nowrap; }
.error { position: absolute; inset: 0.75rem 0.75rem auto 0.75rem; padding: 0.6rem 0.8rem; background: #fff1f0; color: #8a1c12;
         border: 1px solid #f1b5ae; border-radius: 6px; white-space: pre-wrap; z-index: 3; max-height: calc(100% - 1.5rem); overflow: auto; }
.error button { float: right; margin-left: 0.5rem; }
.help { position: absolute; inset: 0.75rem; background: rgba(255,255,255,0.97); border: 1px solid #c9ced8; border-radius: 8px;
        padding: 0.75rem 1rem; overflow: auto; z-index: 4; font-size: 12px; }
.help table { border-collapse: collapse; } .help td { padding: 0.1rem 0.6rem 0.1rem 0; vertical-align: top; }
kbd { font: 11px ui-monospace, monospace; border: 1px solid #c9ced8; border-bottom-width: 2px; border-radius: 3px; padding: 0 0.3rem; background: #fff; white-space: nowrap; }
.panel-toggle { display: none; position: absolute; right: 0.5rem; bottom: 0.5rem; z-index: 2; }
.plots { display: grid; grid-template-columns: repeat(3, minmax(0, 1fr)) minmax(0, 1.1fr); gap: 4px; padding: 4px;
         border-top: 1px solid #dde1e8; min-height: 0; overflow: auto; }
.plot { margin: 0; display: grid; grid-template-rows: auto minmax(0, 1fr); min-height: 0; min-width: 0; border: 1px solid #e6e9ef; border-radius: 3px; background: #fff; }
.plot canvas { width: 100%; height: 100%; min-height: 4.5rem; display: block; }
.plot-head { display: flex; flex-wrap: wrap; gap: 0.1rem 0.5rem; align-items: baseline; padding: 0.15rem 0.35rem 0; font-size: 12px; }
.plot-title { font-weight: 600; }
.legend { display: flex; flex-wrap: wrap; gap: 0 0.2rem; max-height: 2.5em; overflow: auto; }
.legend .key { font: 12px/1.25 system-ui, sans-serif; color: #1d2330; background: none; border: 0; padding: 0 0.2rem; cursor: pointer; display: inline-flex; gap: 0.25rem; align-items: center; }
.legend .key[aria-pressed=false] { color: #6a7180; text-decoration: line-through; }
.legend .swatch { width: 0.9em; height: 0.25em; border-radius: 2px; display: inline-block; }
.log { display: grid; grid-template-rows: auto auto minmax(0, 1fr); min-height: 0; border: 1px solid #e6e9ef; border-radius: 3px; background: #fff; font-size: 12px; }
.log-head { display: flex; gap: 0.3rem; align-items: center; padding: 0.15rem 0.35rem; flex-wrap: wrap; }
.log-head input { flex: 1; min-width: 4rem; font-size: 12px; }
.log-head select { font-size: 12px; max-width: 8rem; }
.log-empty { margin: 0.2rem 0.4rem; }
.log-list { list-style: none; margin: 0; padding: 0; overflow: auto; min-height: 0; }
.log-row { padding: 0.1rem 0.4rem; border-top: 1px solid #f0f2f5; cursor: pointer; }
.log-row:hover, .log-row:focus { background: #eef3fb; outline: none; }
.log-row.stop, .log-row.chattering, .log-row.unavoidable { color: #8a1c12; font-weight: 600; }
.panel { grid-column: 2; grid-row: 1 / 3; border-left: 1px solid #dde1e8; overflow: auto; padding: 0.4rem 0.75rem 1rem; background: #fafbfc; }
.panel h3 { font-size: 12px; text-transform: uppercase; letter-spacing: 0.04em; color: #4a5160; margin: 0.9rem 0 0.35rem; }
.row { display: flex; gap: 0.35rem; align-items: center; margin: 0.2rem 0; flex-wrap: wrap; }
.row > label { flex: 1 1 auto; display: flex; gap: 0.35rem; align-items: center; justify-content: space-between; }
.row input[type=number] { width: 5.2rem; }
.row input[type=range] { flex: 1; min-width: 5rem; }
#share-link { width: 100%; font-size: 12px; }
.dh { width: 100%; border-collapse: collapse; font-size: 12px; margin-top: 0.3rem; }
.dh caption { text-align: left; color: #4a5160; font-size: 12px; }
.dh th { font-weight: 500; color: #4a5160; white-space: nowrap; padding: 0 0.15rem; }
.dh td input { width: 100%; min-width: 0; font-size: 12px; padding: 0.05rem 0.15rem; }
.dh td select { font-size: 11px; max-width: 5.5rem; }
.dh input[aria-invalid=true] { background: #fff1f0; border-color: #c0392b; }
.message { color: #8a1c12; font-size: 12px; white-space: pre-wrap; min-height: 1em; }
.ok { color: #1e6b35; font-size: 12px; }
.palette { display: grid; grid-template-columns: repeat(5, 1fr); gap: 3px; }
.palette button { font-size: 11px; padding: 0.2rem 0; }
.obstacles { list-style: none; padding: 0; margin: 0.25rem 0; max-height: 7rem; overflow: auto; border: 1px solid #e6e9ef; border-radius: 3px; }
.obstacles li { padding: 0.1rem 0.4rem; cursor: pointer; font-size: 12px; }
.obstacles li:focus-visible { outline: 2px solid #2563eb; outline-offset: -2px; }
.obstacles li.selected { background: #fde9a6; }
.pinned-points { list-style: none; padding: 0; margin: 0.25rem 0; border: 1px solid #e6e9ef; border-radius: 3px; }
.pinned-points:empty { display: none; }
.pinned-points li { display: flex; gap: 0.4rem; align-items: center; justify-content: space-between; padding: 0.1rem 0.2rem 0.1rem 0.4rem; font-size: 12px; }
.pinned-points li:focus-visible { outline: 2px solid #2563eb; outline-offset: -2px; }
.pinned-points .remove { font-size: 11px; padding: 0 0.35rem; }
#pin-mode[aria-pressed=true] { background: #a0207a; color: #fff; border-color: #a0207a; }
.view.pinning { cursor: copy; }
.bar { display: flex; gap: 0.4rem; align-items: center; padding: 0.3rem 0.5rem; border-top: 1px solid #dde1e8; background: #fff; }
.bar .title { flex: 1; color: #4a5160; font-size: 12px; overflow: hidden; text-overflow: ellipsis; white-space: nowrap; }
.hint { color: #4a5160; font-size: 12px; }
button:focus-visible, select:focus-visible, input:focus-visible { outline: 2px solid #2563eb; outline-offset: 1px; }
.sp.minimal .plots, .sp.none .plots { display: none; }
.sp.minimal .hud, .sp.none .hud { font-size: 11px; padding: 0.1rem 0.35rem; }
.sp.minimal .notice, .sp.none .notice { font-size: 11px; padding: 0.05rem 0.35rem; }
.sp.minimal:not(.with-stats) .stats, .sp.none:not(.with-stats) .stats { display: none; }
.sp.minimal.with-plot .plots { display: grid; grid-template-columns: minmax(0, 1fr); height: 9rem; }
@container sp (max-width: 900px) {
  .sp.full { grid-template-columns: minmax(0, 1fr); grid-template-rows: minmax(0, 1fr) 12.5rem; }
  .sp.full .panel { grid-column: auto; grid-row: auto; position: absolute; top: 0; right: 0; bottom: 0; width: min(22rem, 92%); z-index: 5; transform: translateX(102%);
                    transition: transform 0.15s; box-shadow: -2px 0 10px rgba(0,0,0,0.15); visibility: hidden; }
  .sp.full.panel-open .panel { transform: none; visibility: visible; }
  .panel-toggle { display: block; }
  .notices[data-corner="bottom-right"] { bottom: 2.6rem; }
  .sp.full.panel-open .panel-toggle { right: calc(min(22rem, 92%) + 0.5rem); }
}
@container sp (max-width: 700px) {
  .plots { grid-template-columns: repeat(2, minmax(0, 1fr)); grid-auto-rows: 9.5rem; }
}
@container sp (max-width: 560px) {
  .sp.full { grid-template-rows: minmax(0, 1fr) 13rem; }
  .plots { grid-template-columns: minmax(0, 1fr); grid-auto-rows: 10rem; }
  .stats, .hud { font-size: 10.5px; }
  .camera-thumb { width: 96px; height: 72px; bottom: 5rem; }
  .notices, .notices[data-corner] { left: 0.5rem; right: auto; top: auto; bottom: 2.6rem; max-width: calc(100% - 1rem); }
}
`;
