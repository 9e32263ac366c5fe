// `skeleton-avoidance/element`: importing it defines <skeleton-playground>.
//
//   import 'skeleton-avoidance/element';
//   <skeleton-playground scenario="human-panda" controls="minimal"></skeleton-playground>
//
// Attributes: scenario (an example name, a URL of a .json scenario, or inline
// JSON), controls ("full" | "minimal" | "none"), plot ("clearance" | "dh" |
// "qdot"), backend ("auto" | "webgpu" | "webgl2"), view ("auto" | "3d" | "top"
// | "front" | "side"), speed, paused, stats, share, autoplay, fill.

/** The widget inside the element: the world, the viewer, the panel and the plots. */
export interface Playground {
  /** `"webgpu"` or `"webgl2"` once started. */
  readonly backend: 'webgpu' | 'webgl2' | null;
  /** The simulated world (the library's `World`). */
  readonly world: import('./index.js').World | null;
  /** The renderer (the library's `Viewer`). */
  readonly viewer: import('./index.js').Viewer | null;
  /** Pauses or resumes the simulation. */
  toggleRun(): void;
  /** Loads a scenario (an example name or a scenario object) and resets. */
  start(scenario: string | import('./index.js').Scenario): Promise<void>;
  /** Shows a message over the view. */
  showError(message: string): void;
  /** Stops drawing and frees the world and the viewer. */
  destroy(): void;
}

/** The widget without the element: `new Playground(root, options)`, then `start(scenario)`. */
export declare const Playground: {
  new (
    root: ShadowRoot | HTMLElement,
    options?: {
      controls?: 'full' | 'minimal' | 'none' | undefined;
      backend?: 'auto' | 'webgpu' | 'webgl2' | undefined;
      view?: 'auto' | '3d' | 'top' | 'front' | 'side' | undefined;
      speed?: number | undefined;
      plot?: 'clearance' | 'dh' | 'qdot' | undefined;
      stats?: boolean | undefined;
    },
  ): Playground;
};

/** `<skeleton-playground>`. */
export declare class SkeletonPlayground extends HTMLElement {
  /** Resolves to the Playground once the first frames are drawn; rejects with the failure shown inside. */
  readonly ready: Promise<Playground>;
  /** The Playground once `ready` resolves, else null. */
  readonly playground: Playground | null;
}

/** Loads and initialises the wasm once per page; resolves to the library's exports. */
export declare function loadWasm(): Promise<typeof import('./index.js')>;

declare global {
  interface HTMLElementTagNameMap {
    'skeleton-playground': SkeletonPlayground;
  }
}
