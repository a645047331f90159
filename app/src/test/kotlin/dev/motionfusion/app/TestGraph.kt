package dev.motionfusion.app

import android.app.Notification
import android.app.Service
import android.content.Context
import android.hardware.SensorManager
import android.os.Looper
import androidx.core.app.ServiceCompat
import dev.motionfusion.app.calibration.CalibrationSampleSource
import dev.motionfusion.app.calibration.CalibrationStore
import dev.motionfusion.app.platform.AppFiles
import dev.motionfusion.app.platform.Clock
import dev.motionfusion.app.platform.DiskExecutor
import dev.motionfusion.app.platform.FolderLocks
import dev.motionfusion.app.record.BatterySource
import dev.motionfusion.app.record.BatteryState
import dev.motionfusion.app.record.CoreSessionFormat
import dev.motionfusion.app.record.SessionFormat
import dev.motionfusion.app.settings.SettingsStore
import dev.motionfusion.app.stream.StreamService
import dev.motionfusion.app.stream.WifiLocks
import dev.motionfusion.stream.StreamServerSettings
import java.io.File
import kotlinx.coroutines.CoroutineDispatcher
import kotlinx.coroutines.Dispatchers
import kotlin.coroutines.CoroutineContext
import java.util.concurrent.LinkedBlockingDeque
import org.robolectric.RuntimeEnvironment
import org.robolectric.Shadows.shadowOf

/**
 * The disk executor of the tests: tasks wait in a queue until the test runs them ([runAll]) on
 * a background thread of its own, so a test sees the UI between "Record pressed" and "repair
 * done", and a task that would run on the main thread fails (FolderLocks' check).
 */
internal class ManualDiskExecutor(private val locks: FolderLocks = FolderLocks()) : DiskExecutor {
    private val tasks = LinkedBlockingDeque<() -> Unit>()
    val pending: Int get() = tasks.size

    override fun execute(folder: File?, task: () -> Unit) {
        tasks += { locks.withFolder(folder, task) }
    }

    /** Runs every queued task (and those they queue) on a background thread; rethrows a task's failure. */
    fun runAll(): Int {
        var n = 0
        var failure: Throwable? = null
        while (failure == null) {
            val task = tasks.poll() ?: break
            val t = Thread { try { task() } catch (e: Throwable) { failure = e } }
            t.start()
            t.join()
            n++
        }
        failure?.let { throw AssertionError("disk task failed", it) }
        return n
    }
}

/** A clock the test sets. */
internal class FakeClock(var elapsedNs: Long = 5_000_000_000L, var wallMs: Long = 1_764_165_792_123L) : Clock {
    override fun elapsedRealtimeNanos(): Long = elapsedNs
    override fun wallClockMs(): Long = wallMs
}

/** Wi-Fi locks that are only their modes: [held] lists those taken and not released. */
internal class FakeWifiLocks : WifiLocks {
    val held = ArrayList<Int>()

    override fun acquire(mode: Int, tag: String): () -> Unit {
        held += mode
        return { held.remove(mode) }
    }
}

/** A battery the test sets. */
internal class FakeBattery(@Volatile var state: BatteryState = BatteryState(80, false)) : BatterySource {
    var reads = 0
    override fun read(): BatteryState = state.also { reads++ }
}

/**
 * Runs [block] on a thread of its own and returns its result (rethrowing its failure): a test's
 * own disk work (files it prepares or reads back, `Context.getFilesDir()`, SharedPreferences)
 * stays off the main thread, where StrictMode fails the test (StrictTestApp).
 */
internal fun <T> offMainThread(block: () -> T): T {
    var result: Result<T>? = null
    val t = Thread { result = runCatching(block) }
    t.start()
    t.join()
    return result!!.getOrThrow()
}

/**
 * A dispatcher whose tasks wait until the test runs them, newest first ([runNewestFirst], off the
 * main thread): the worst order a dispatcher with several threads could pick for background writes.
 */
internal class HeldDispatcher : CoroutineDispatcher() {
    private val tasks = ArrayList<Runnable>()

    override fun dispatch(context: CoroutineContext, block: Runnable) {
        synchronized(tasks) { tasks += block }
    }

    fun runNewestFirst() = offMainThread {
        while (true) {
            val task = synchronized(tasks) { tasks.removeLastOrNull() } ?: break
            task.run()
        }
    }
}

/**
 * The application graph of a Robolectric test: capture pumped by the test, the tasks of both disk
 * queues ([disk], [recordingDisk]) run by the test. The settings and the calibration are read from storage as the graph is made ([loadStores];
 * false: they stay unread until the test runs the disk tasks, as in the first moments of a process).
 */
internal class TestGraph(
    format: SessionFormat = CoreSessionFormat,
    minFreeBytes: Long = 0L,
    enterForeground: (Service, Int, Notification, Int) -> Unit = ServiceCompat::startForeground,
    val battery: FakeBattery = FakeBattery(),
    /** The calibration screen's readings; null: the capture's. */
    calibrationSource: CalibrationSampleSource? = null,
    loadStores: Boolean = true,
    /** The live stream's port (0: one the system picks) and the addresses the Stream screen shows. */
    streamPort: Int = 0,
    streamAddresses: List<String> = listOf("192.168.1.23"),
    streamSettings: StreamServerSettings = StreamServerSettings(),
    /** Starts the stream's foreground service; Robolectric records the intent (the test creates the service from it). */
    streamKeepAlive: () -> Int? = { StreamService.start(RuntimeEnvironment.getApplication()) },
    /** A laptop's remote start and stop (AppGraph's; the app passes RecordingService's entry points); default: not available. */
    remoteRecordStart: (dev.motionfusion.core.session.RemoteStart) -> String? = { "recording is not available" },
    remoteRecordStop: () -> Unit = {},
) {
    val app = RuntimeEnvironment.getApplication() as MotionFusionApp
    private val locks = FolderLocks()
    /** The screens' disk queue. */
    val disk = ManualDiskExecutor(locks)
    /** The recording's own disk queue. */
    val recordingDisk = ManualDiskExecutor(locks)
    /** The stream's control executor (the server's start and stop), run by [settle] as the disk queues are. */
    val streamControl = ManualDiskExecutor(locks)
    val clock = FakeClock()
    /** The Wi-Fi locks held, by mode (Robolectric cannot load WifiManager's shadow with these framework jars). */
    val wifiLocks = FakeWifiLocks()
    var captureNs = 0L
    val graph = AppGraph(
        app.getSystemService(SensorManager::class.java), AppFiles { app.filesDir }, SettingsStore(app),
        { app.getSharedPreferences(CalibrationStore.PREFS, Context.MODE_PRIVATE) },
        locks = locks, disk = disk, recordingDisk = recordingDisk, clock = clock, format = format, minFreeBytes = minFreeBytes, captureThread = false,
        captureClock = { captureNs }, enterForeground = enterForeground, battery = battery,
        // The calibration's fits run on the main thread: each step is complete when the looper is idle.
        calibrationCompute = Dispatchers.Main.immediate, calibrationSource = calibrationSource,
        streamPort = streamPort, streamAddresses = { streamAddresses },
        streamControl = { r -> streamControl.execute(null) { r.run() } }, streamSettings = streamSettings, streamKeepAlive = streamKeepAlive,
        streamLookup = { r -> streamControl.execute(null) { r.run() } },
        wifiLocks = wifiLocks, remoteRecordStart = remoteRecordStart, remoteRecordStop = remoteRecordStop,
    ).also { app.graph = it }
    val capture get() = graph.capture

    init {
        if (loadStores) settle()
    }

    /** The capture thread's work for what was delivered, including the end of the reorder window; then the main thread's. */
    fun pump() {
        while (capture.pump() > 0) Unit
        captureNs += 1_000_000_000L
        capture.pump()
        shadowOf(Looper.getMainLooper()).idle()
    }

    /**
     * [settle], the main thread's tasks run one at a time: returns the longest of them on [clock]
     * (the work they did, as the fakes advance it) and how many ran.
     */
    fun settleTimed(): Pair<Long, Int> {
        val main = shadowOf(Looper.getMainLooper())
        var longest = 0L
        var tasks = 0
        fun runMain() {
            while (!main.isIdle) {
                val t0 = clock.elapsedNs
                main.runOneTask()
                longest = maxOf(longest, clock.elapsedNs - t0)
                tasks++
            }
        }
        do {
            runMain()
            val n = recordingDisk.runAll() + disk.runAll() + streamControl.runAll()
            capture.pump()
            runMain()
        } while (n > 0 || disk.pending > 0 || recordingDisk.pending > 0 || streamControl.pending > 0)
        return longest to tasks
    }

    /** Disk tasks and main-thread work until both are quiet. */
    fun settle() {
        do {
            shadowOf(Looper.getMainLooper()).idle()
            val n = recordingDisk.runAll() + disk.runAll() + streamControl.runAll()
            capture.pump()
            shadowOf(Looper.getMainLooper()).idle()
        } while (n > 0 || disk.pending > 0 || recordingDisk.pending > 0 || streamControl.pending > 0)
    }
}
