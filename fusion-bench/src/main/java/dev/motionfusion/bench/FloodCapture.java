/*
 * The app's capture (dev.motionfusion.app.fusion.Capture) set up for the benchmarks: sensors that
 * are only a set of kinds (the benchmark is the sensor thread and offers into the ring), the
 * default settings, and Java names for the capture's module-internal calls (Kotlin gives
 * internal members a "$app" suffix).
 */
package dev.motionfusion.bench;

import dev.motionfusion.app.fusion.Capture;
import dev.motionfusion.app.fusion.CaptureTap;
import dev.motionfusion.app.settings.LiveSettings;
import dev.motionfusion.app.sensor.EventRing;
import dev.motionfusion.app.sensor.SamplingRate;
import dev.motionfusion.app.sensor.SensorInfo;
import dev.motionfusion.app.sensor.SensorKind;
import dev.motionfusion.app.sensor.SensorSource;
import dev.motionfusion.core.event.SessionStream;
import java.util.Collections;
import java.util.EnumSet;
import java.util.Map;
import java.util.Set;
import kotlinx.coroutines.CoroutineScopeKt;
import kotlinx.coroutines.Dispatchers;
import kotlinx.coroutines.flow.StateFlowKt;

final class FloodCapture {
    private FloodCapture() {}

    /**
     * Every live-screen kind present; registration does nothing. With a report latency (hardware
     * batching), flushes complete at once: the benchmark, as the sensor thread, delivers a FIFO's
     * events when it offers them.
     */
    static final class Kinds implements SensorSource {
        private final int latencyUs;
        private SamplingRate rate;
        private int registeredLatencyUs;

        Kinds() { this(0); }

        Kinds(int latencyUs) { this.latencyUs = latencyUs; }

        // Raw Map: the Android framework (android.hardware.Sensor) is not on this module's classpath.
        @SuppressWarnings("rawtypes")
        @Override public Map getSensors() { return Collections.emptyMap(); }
        @Override public Set<SensorKind> getAvailableKinds() { return EnumSet.allOf(SensorKind.class); }
        @Override public Map<SensorKind, SensorInfo> getInfo() { return Collections.emptyMap(); }
        @Override public SamplingRate getRegisteredRate() { return rate; }
        @Override public void start(SamplingRate r, Set<? extends SessionStream> streams) { rate = r; registeredLatencyUs = latencyUs; }
        @Override public void stop() { rate = null; registeredLatencyUs = 0; }
        @Override public int reportLatencyUs(SamplingRate r, Set<? extends SessionStream> streams) { return latencyUs; }
        @Override public int getRegisteredLatencyUs() { return registeredLatencyUs; }
        @Override public double getMaxEventsPerSecond() { return rate == null ? 0.0 : 200.0; }
        @Override public void immediate(boolean on) { }
        @Override public void flush() { }
        @Override public boolean getFlushed() { return true; }
    }

    /** A capture with its own capture thread, running. */
    static Capture threaded(EventRing ring) {
        return create(ring, true, 0);
    }

    /** A capture with its own capture thread, running, its sensors registered with a report latency of [latencyUs] (hardware batching). */
    static Capture threaded(EventRing ring, int latencyUs) {
        return create(ring, true, latencyUs);
    }

    /** A capture without a thread: the caller pumps it. */
    static Capture manual(EventRing ring) {
        return create(ring, false, 0);
    }

    private static Capture create(EventRing ring, boolean thread, int latencyUs) {
        Capture c = new Capture(ring, new Kinds(latencyUs), StateFlowKt.MutableStateFlow(new LiveSettings()),
            CoroutineScopeKt.CoroutineScope(Dispatchers.getUnconfined()), StateFlowKt.MutableStateFlow(null), 30_000_000L, System::nanoTime, thread, 4_000_000L, 100_000_000L);
        c.acquire();
        return c;
    }

    static void attach(Capture c, CaptureTap tap) {
        c.attach$app(tap, new LiveSettings(), null, null);
        if (!c.isRunning()) throw new IllegalStateException("not running");
    }

    static void detach(Capture c, CaptureTap tap) {
        c.detach$app(tap);
        c.pump$app(); // the capture is synchronised: safe beside its thread, and finishes at once without one
    }

    static int pump(Capture c) {
        return c.pump$app();
    }
}
