package dev.motionfusion.app.live

import android.content.Context
import android.hardware.SensorManager
import android.os.Handler
import android.os.HandlerThread
import android.os.Looper
import android.os.Process
import dev.motionfusion.app.sensor.SensorInfo
import dev.motionfusion.app.sensor.SensorKind
import dev.motionfusion.app.sensor.SensorSource
import dev.motionfusion.app.settings.SettingsStore
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.Job
import kotlinx.coroutines.android.asCoroutineDispatcher
import kotlinx.coroutines.cancel
import kotlinx.coroutines.flow.MutableStateFlow
import kotlinx.coroutines.flow.StateFlow
import kotlinx.coroutines.flow.asStateFlow
import kotlinx.coroutines.flow.collectLatest
import kotlinx.coroutines.flow.distinctUntilChanged
import kotlinx.coroutines.flow.map
import kotlinx.coroutines.launch

/**
 * Runs the fusion on the device: the [SensorSource] stream (never conflated) is folded sample by
 * sample into a [FusionPipeline] on a dedicated HandlerThread (listeners and filter on the same
 * thread, nothing per sample on the main thread), and the result is published as [state], which
 * the UI samples at display rate.
 *
 * The engine lives as long as the process ([LiveEngines]), so the filter survives configuration
 * changes and activity re-creation. Capture runs only between [start] and [stop] (reference
 * counted): when nobody needs it, listeners are unregistered, the coroutines cancelled and the
 * thread quit. [start], [stop] and [updateSettings] are called on the main thread.
 */
class FusionEngine(sensorManager: SensorManager, private val store: SettingsStore) {
    private val source = SensorSource(sensorManager)

    /** The kinds the device has. */
    val available: Set<SensorKind> = source.availableKinds()

    /** Name, vendor and limits of each sensor the device has. */
    val sensorInfo: Map<SensorKind, SensorInfo> = available.associateWith { source.info(it)!! }

    private val settingsFlow = MutableStateFlow(store.load())

    /** The settings in force. */
    val settings: StateFlow<LiveSettings> = settingsFlow.asStateFlow()

    private val pipeline = FusionPipeline(available, settingsFlow.value)
    private val stateFlow = MutableStateFlow(pipeline.snapshot())

    /** The latest published fusion result. */
    val state: StateFlow<FusionState> = stateFlow.asStateFlow()

    private var users = 0
    private var thread: HandlerThread? = null
    private var scope: CoroutineScope? = null

    @Volatile
    private var publishPending = false
    private val publish = Runnable {
        publishPending = false
        stateFlow.value = synchronized(pipeline) { pipeline.snapshot() }
    }

    /** True while listeners are registered (between the first [start] and the last [stop]). */
    val isRunning: Boolean get() = thread != null

    /** The fusion thread's looper while running (for tests that drain it). */
    internal val looper: Looper? get() = thread?.looper

    /** Starts capture for one more user. */
    fun start() {
        users++
        if (users > 1) return
        val t = HandlerThread("fusion", Process.THREAD_PRIORITY_URGENT_DISPLAY).apply { start() }
        val handler = Handler(t.looper)
        publishPending = false
        val s = CoroutineScope(Job() + handler.asCoroutineDispatcher("fusion"))
        thread = t
        scope = s
        s.launch {
            settingsFlow.collect {
                synchronized(pipeline) { pipeline.reconfigure(it) }
                schedulePublish(handler)
            }
        }
        s.launch {
            // Re-register only when the requested rate changes; every sample reaches the pipeline.
            settingsFlow.map { it.rate }.distinctUntilChanged().collectLatest { rate ->
                source.samples(available, rate, handler).collect { sample ->
                    // Uncontended except for the moments after a restart while the old thread drains.
                    synchronized(pipeline) { pipeline.onSample(sample) }
                    schedulePublish(handler)
                }
            }
        }
    }

    /** Stops capture for one user; the last one unregisters the listeners and quits the thread. */
    fun stop() {
        if (users == 0) return
        users--
        if (users > 0) return
        scope?.cancel()
        scope = null
        // quitSafely lets the cancellation (unregisterListener in awaitClose) run first.
        thread?.quitSafely()
        thread = null
    }

    /** Stores [s] and applies it to the running filter at once. */
    fun updateSettings(s: LiveSettings) {
        store.save(s)
        settingsFlow.value = s
        if (thread == null) {
            // Not capturing: apply now so that the state shows the new mode.
            stateFlow.value = synchronized(pipeline) {
                pipeline.reconfigure(s)
                pipeline.snapshot()
            }
        }
    }

    /** The filter settings in force in the pipeline (for tests and diagnostics). */
    internal fun filterSettingsInUse() = synchronized(pipeline) { pipeline.filter.settings }

    /** After a batch of samples, one publication: the UI never waits for every sample. */
    private fun schedulePublish(handler: Handler) {
        if (publishPending) return
        publishPending = true
        handler.post(publish)
    }
}

/** The process-wide [FusionEngine]: one per application, created on first use. */
object LiveEngines {
    private var engine: FusionEngine? = null
    private var owner: Context? = null

    /** The engine of [context]'s application (main thread). */
    fun get(context: Context): FusionEngine {
        val app = context.applicationContext
        engine?.let { if (owner === app) return it }
        // A new Application (only in tests, where each test has its own): start afresh.
        engine?.let { while (it.isRunning) it.stop() }
        val e = FusionEngine(app.getSystemService(SensorManager::class.java), SettingsStore(app))
        engine = e
        owner = app
        return e
    }
}
