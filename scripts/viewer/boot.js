// Starts Foxglove Studio (the App of @foxglove/studio-base 1.48, a UMD bundle that puts its
// exports on window) as the desktop/web app would, with an in-memory layout store that starts
// empty: the layout comes in through the app's own "Import layout" button, as a user's would.
(async function () {
  const Studio = window;
  const layouts = new Map();
  const layoutStorage = {
    async list() { return [...layouts.values()]; },
    async get(_ns, id) { return layouts.get(id); },
    async put(_ns, layout) { layouts.set(layout.id, layout); return layout; },
    async delete(_ns, id) { layouts.delete(id); },
    async importLayouts() {},
    async migrateUnnamespacedLayouts() {},
  };
  const settings = new Map([["colorScheme", "light"], ["telemetry.telemetryEnabled", false], ["telemetry.crashReportingEnabled", false]]);
  const listeners = new Map();
  const appConfiguration = {
    get: (key) => settings.get(key),
    set: async (key, value) => {
      settings.set(key, value);
      (listeners.get(key) || []).forEach((cb) => cb(value));
    },
    addChangeListener: (key, cb) => listeners.set(key, [...(listeners.get(key) || []), cb]),
    removeChangeListener: (key, cb) => listeners.set(key, (listeners.get(key) || []).filter((x) => x !== cb)),
  };
  Studio.overwriteFetch();
  await Studio.waitForFonts();
  await Studio.initI18n();
  const dataSources = [new Studio.McapLocalDataSourceFactory(), new Studio.RemoteDataSourceFactory()];
  ReactDOM.render(
    React.createElement(Studio.App, {
      deepLinks: [location.href],
      dataSources,
      appConfiguration,
      layoutStorage,
      extensionLoaders: [],
      enableGlobalCss: true,
    }),
    document.getElementById("root"),
  );
  window.rstsBooted = true;
})().catch((e) => console.error("rsts boot failed:", e));
