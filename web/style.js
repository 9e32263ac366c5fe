// The playground's stylesheet, adopted by each widget's shadow root.
export const STYLE = `
:host { display: block; position: relative; font: 13px/1.35 system-ui, sans-serif; color: #1d2330; background: #fafbfc;
        border: 1px solid #dde1e8; border-radius: 6px; overflow: hidden; min-height: 320px; }
:host([fill]) { border: 0; border-radius: 0; height: 100vh; }
* { box-sizing: border-box; }
.sp { display: grid; height: 100%; grid-template-columns: 1fr; grid-template-rows: 1fr auto; }
.sp.full { grid-template-columns: 1fr 20rem; grid-template-rows: 1fr 11rem; }
.stage { position: relative; min-height: 0; min-width: 0; }
.view { width: 100%; height: 100%; display: block; touch-action: none; cursor: crosshair; outline: none; }
.stats { position: absolute; left: 0.5rem; top: 0.5rem; background: rgba(255,255,255,0.85); border: 1px solid #dde1e8;
         border-radius: 4px; padding: 0.2rem 0.45rem; font: 11px/1.3 ui-monospace, monospace; white-space: pre; pointer-events: none; }
.hud { position: absolute; right: 0.5rem; top: 0.5rem; background: rgba(255,255,255,0.88); border: 1px solid #dde1e8;
       border-radius: 4px; padding: 0.25rem 0.5rem; font: 11px/1.35 ui-monospace, monospace; white-space: pre; pointer-events: none; }
.notices { position: absolute; left: 0.5rem; bottom: 0.5rem; display: flex; flex-direction: column; gap: 0.25rem; pointer-events: none; }
.notice { background: #1d2330; color: #fff; border-radius: 4px; padding: 0.2rem 0.5rem; font-size: 12px; opacity: 0.9; }
.notice.stop, .notice.chattering { background: #a52714; }
.error { position: absolute; inset: 0.75rem 0.75rem auto 0.75rem; padding: 0.6rem 0.8rem; background: #fff1f0; color: #8a1c12;
         border: 1px solid #f1b5ae; border-radius: 6px; white-space: pre-wrap; z-index: 3; }
.error button { float: right; margin-left: 0.5rem; }
.help { position: absolute; inset: 2rem; background: rgba(255,255,255,0.97); border: 1px solid #c9ced8; border-radius: 8px;
        padding: 1rem 1.25rem; overflow: auto; z-index: 4; }
.help table { border-collapse: collapse; } .help td { padding: 0.15rem 0.75rem 0.15rem 0; }
kbd { font: 11px ui-monospace, monospace; border: 1px solid #c9ced8; border-bottom-width: 2px; border-radius: 3px; padding: 0 0.3rem; background: #fff; }
.plots { display: grid; grid-template-columns: repeat(3, 1fr); gap: 4px; padding: 4px; border-top: 1px solid #dde1e8; min-height: 0; }
.plots canvas { width: 100%; height: 100%; min-height: 0; display: block; border: 1px solid #e6e9ef; border-radius: 3px; }
.panel { grid-column: 2; grid-row: 1 / 3; border-left: 1px solid #dde1e8; overflow: auto; padding: 0.4rem 0.75rem 1rem; }
.panel h3 { font-size: 12px; text-transform: uppercase; letter-spacing: 0.04em; color: #556; margin: 0.9rem 0 0.35rem; }
.row { display: flex; gap: 0.35rem; align-items: center; margin: 0.2rem 0; flex-wrap: wrap; }
.row > label { flex: 1 1 auto; display: flex; gap: 0.35rem; align-items: center; justify-content: space-between; }
.row input[type=number] { width: 5.2rem; }
.row input[type=range] { flex: 1; }
.dh { width: 100%; border-collapse: collapse; font-size: 12px; }
.dh th { font-weight: 500; color: #556; } .dh td input { width: 100%; min-width: 0; font-size: 12px; }
.message { color: #8a1c12; font-size: 12px; white-space: pre-wrap; min-height: 1em; }
.ok { color: #1e6b35; font-size: 12px; }
.palette { display: grid; grid-template-columns: repeat(5, 1fr); gap: 3px; }
.palette button { font-size: 11px; padding: 0.2rem 0; }
.obstacles { list-style: none; padding: 0; margin: 0.25rem 0; max-height: 7rem; overflow: auto; border: 1px solid #e6e9ef; border-radius: 3px; }
.obstacles li { padding: 0.1rem 0.4rem; cursor: pointer; font-size: 12px; }
.obstacles li.selected { background: #fde9a6; }
.bar { display: flex; gap: 0.4rem; align-items: center; padding: 0.3rem 0.5rem; border-top: 1px solid #dde1e8; background: #fff; }
.bar .title { flex: 1; color: #556; font-size: 12px; overflow: hidden; text-overflow: ellipsis; white-space: nowrap; }
.hint { color: #667; font-size: 11px; }
.sp.minimal .plots, .sp.none .plots { display: none; }
.sp.minimal .hud, .sp.none .hud { font-size: 10px; padding: 0.1rem 0.35rem; opacity: 0.9; }
.sp.minimal .notice, .sp.none .notice { font-size: 10px; padding: 0.05rem 0.35rem; }
.sp.minimal .notice:nth-last-child(n+3), .sp.none .notice:nth-last-child(n+3) { display: none; }
.sp.minimal:not(.with-stats) .stats, .sp.none:not(.with-stats) .stats { display: none; }
.sp.minimal.with-plot .plots { display: grid; grid-template-columns: 1fr; height: 8rem; }
`;
