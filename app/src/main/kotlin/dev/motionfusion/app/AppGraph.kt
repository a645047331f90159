package dev.motionfusion.app

import android.app.Notification
import android.app.Service
import android.content.Context
import android.content.SharedPreferences
import android.hardware.SensorManager
import androidx.core.app.ServiceCompat
import dev.motionfusion.app.calibration.CalibrationDependencies
import dev.motionfusion.app.calibration.CalibrationSampleSource
import dev.motionfusion.app.calibration.CalibrationStore
import dev.motionfusion.app.calibration.CaptureSampleSource
import dev.motionfusion.app.fusion.Capture
import dev.motionfusion.app.settings.LiveSettings
import dev.motionfusion.app.platform.AppFiles
import dev.motionfusion.app.platform.AppVersion
import dev.motionfusion.app.platform.Clock
import dev.motionfusion.app.platform.DiskExecutor
import dev.motionfusion.app.platform.FolderLocks
import dev.motionfusion.app.platform.SerialDiskExecutor
import dev.motionfusion.app.record.CoreSessionFormat
import dev.motionfusion.app.record.BatterySource
import dev.motionfusion.app.record.BatteryState
import dev.motionfusion.app.record.RecordingDependencies
import dev.motionfusion.app.record.RecordingInProgress
import dev.motionfusion.app.record.RecordingMetadata
import dev.motionfusion.app.record.StickyBattery
import dev.motionfusion.app.record.Recordings
import dev.motionfusion.app.record.SessionFormat
import dev.motionfusion.app.sensor.EventRing
import dev.motionfusion.app.sensor.SensorHub
import dev.motionfusion.app.sessions.CoreSessionLibrary
import dev.motionfusion.app.sessions.SessionLibrary
import dev.motionfusion.app.sessions.SessionsDependencies
import dev.motionfusion.app.sessions.SessionsRepository
import dev.motionfusion.app.settings.SettingsRepository
import dev.motionfusion.app.settings.SettingsStore
import dev.motionfusion.app.record.RecordingService
import dev.motionfusion.app.stream.StreamController
import dev.motionfusion.app.stream.StreamDependencies
import dev.motionfusion.app.stream.StreamService
import dev.motionfusion.app.stream.WifiLocks
import dev.motionfusion.stream.StreamServerSettings
import dev.motionfusion.core.session.SessionCalibration
import java.util.concurrent.Executor
import java.util.concurrent.Executors
import kotlinx.coroutines.CoroutineDispatcher
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.Dispatchers
import kotlinx.coroutines.SupervisorJob
import kotlinx.coroutines.asCoroutineDispatcher
import kotlinx.coroutines.flow.StateFlow

/**
 * The application's object graph: one of each long-lived part, built once and passed by
 * constructor. Screens and the recording service reach the parts they need through the small
 * interfaces of their packages ([RecordingDependencies], [SessionsDependencies],
 * [CalibrationDependencies], [SettingsRepository.Provider]), which [MotionFusionApp] implements; tests build the graph with
 * fakes (a manual disk executor, a fake clock, a failing session format).
 */
internal class AppGraph(
    sensorManager: SensorManager,
    /** The app's files folder, resolved on the disk executor. */
    files: AppFiles,
    settingsStore: SettingsStore,
    /** Where the calibration screen's "use in the live filter" is kept (opened on the disk executor). */
    calibrationPrefs: () -> SharedPreferences,
    /** The folder locks both disk queues hold (one session folder is never worked on by both at once). */
    locks: FolderLocks = FolderLocks(),
    /** The screens' disk queue: reads of the sessions and their details, exports, shares, rename, delete, the stores. */
    val disk: DiskExecutor = SerialDiskExecutor(locks),
    /** The recording's own disk queue: a Record never waits behind an export, a share or a detail read. */
    override val recordingDisk: DiskExecutor = SerialDiskExecutor(locks, "recording-disk"),
    override val clock: Clock = Clock.System,
    override val format: SessionFormat = CoreSessionFormat,
    override val library: SessionLibrary = CoreSessionLibrary,
    override val minFreeBytes: Long = 32L * 1024 * 1024,
    /** False in tests that run the capture step by step ([Capture.pump]). */
    captureThread: Boolean = true,
    ringCapacity: Int = Capture.DEFAULT_RING_CAPACITY,
    captureClock: () -> Long = System::nanoTime,
    private val enterForeground: (Service, Int, Notification, Int) -> Unit = ServiceCompat::startForeground,
    override val battery: BatterySource = BatterySource { BatteryState(null, false) },
    override val calibrationCompute: CoroutineDispatcher = Dispatchers.Default,
    /** The calibration screen's readings; null: the capture's ([CaptureSampleSource]). */
    calibrationSource: CalibrationSampleSource? = null,
    /** The app's version name (for the stream's hello); read when a client pairs. */
    appVersion: () -> String = { "" },
    /** The live stream's port and the addresses the Stream screen shows (tests: port 0 and fixed addresses). */
    streamPort: Int = StreamController.PORT,
    streamAddresses: () -> List<String> = StreamController::siteLocalAddresses,
    /** Where the stream's server starts and stops (tests: a queue they run). */
    streamControl: Executor = Executors.newSingleThreadExecutor { r -> Thread(r, "stream-control").apply { isDaemon = true } },
    streamSettings: StreamServerSettings = StreamServerSettings(),
    /** Starts the stream's foreground service (StreamService.start); returns why the system refused, or null. */
    streamKeepAlive: () -> Int? = { null },
    /** Where the UDP push's target is looked up (StreamController's lookup). */
    streamLookup: Executor = StreamController.LOOKUP,
    /** The Wi-Fi locks the stream's service holds (StreamService.systemWifiLocks; none by default). */
    override val wifiLocks: WifiLocks = WifiLocks { _, _ -> null },
    /** A laptop's remote start: the recording service started as Record does (RecordingService.startRemote); why refused, or null. */
    remoteRecordStart: (dev.motionfusion.core.session.RemoteStart) -> String? = { "recording is not available" },
    /** A laptop's remote stop (RecordingService.stop). */
    remoteRecordStop: () -> Unit = {},
) : RecordingDependencies, SessionsDependencies, CalibrationDependencies, StreamDependencies {
    /** Main-thread scope of the application (it lives as long as the process). */
    val scope = CoroutineScope(SupervisorJob() + Dispatchers.Main.immediate)

    override val io: CoroutineDispatcher = Executor { r -> disk.execute(null) { r.run() } }.asCoroutineDispatcher()
    val settingsRepository = SettingsRepository(settingsStore, io, scope)
    override val settings: StateFlow<LiveSettings> get() = settingsRepository.settings
    private val ring = EventRing(ringCapacity)
    private val hub = SensorHub(sensorManager, ring)
    override val calibrationStore = CalibrationStore(
        { files.folder("calibration") }, CalibrationDependencies.deviceKey(hub.sensors), calibrationPrefs, io, scope,
    )
    override val capture = Capture(ring, hub, settingsRepository.settings, scope, calibrationStore.active, nanoTime = captureClock, runThread = captureThread)
    override val calibrationSource: CalibrationSampleSource = calibrationSource ?: CaptureSampleSource(capture)
    override val recordings = Recordings()

    /** The live stream; its hello carries the metadata a recording started now would write (RecordingMetadata, as the service builds it). */
    val stream = StreamController(capture, {
        val stored = calibrationStore.sessionCalibration()
        RecordingMetadata.create(
            appVersion(),
            capture.sensors, settings.value.rate, 0,
            capture.filterSettingsInUse(),
            RecordingMetadata.anchorNow(),
            stored?.copy(appliedInLiveFilter = capture.calibrationInUse() != null),
        )
    }, scope, streamPort, streamAddresses, control = streamControl, serverSettings = streamSettings, keepAlive = streamKeepAlive, lookup = streamLookup,
        log = { message, e -> android.util.Log.w("StreamController", message, e) },
        recording = dev.motionfusion.app.stream.RecordingRemote(recordings, remoteRecordStart, remoteRecordStop), sensorClock = clock::elapsedRealtimeNanos)
    override val streamController: StreamController get() = stream
    override val sessions = SessionsRepository(files, format, locks)
    override val inProgress = RecordingInProgress { files.folder(RecordingInProgress.FILE_NAME) }

    override suspend fun awaitStores() {
        settingsRepository.awaitLoaded()
        calibrationStore.awaitLoaded()
    }

    override fun sessionCalibration(): SessionCalibration? = calibrationStore.sessionCalibration()

    override val notificationsAnswered: Boolean get() = settingsRepository.notificationsAnswered

    override fun setNotificationsAnswered() = settingsRepository.markNotificationsAnswered()

    override fun startForeground(service: Service, id: Int, notification: Notification, type: Int) =
        enterForeground(service, id, notification, type)

    companion object {
        /** The graph of a running app. Nothing here touches the disk: folders and files are opened on the disk executor. */
        fun create(context: Context): AppGraph = AppGraph(
            context.getSystemService(SensorManager::class.java),
            AppFiles { context.filesDir },
            SettingsStore(context),
            { context.getSharedPreferences(CalibrationStore.PREFS, Context.MODE_PRIVATE) },
            battery = StickyBattery(context),
            appVersion = { AppVersion.of(context) },
            streamKeepAlive = { StreamService.start(context) },
            wifiLocks = StreamService.systemWifiLocks(context),
            remoteRecordStart = { start -> RecordingService.startRemote(context, start)?.let { context.getString(it.text) } },
            remoteRecordStop = { RecordingService.stop(context) },
        )
    }
}
