package dev.motionfusion.app.record

import dev.motionfusion.app.ui.Formats
import dev.motionfusion.app.settings.RecordingLimits
import dev.motionfusion.core.event.SessionStream
import android.app.Notification
import android.app.NotificationManager
import android.app.PendingIntent
import android.app.Service
import android.content.Context
import android.content.Intent
import android.content.pm.ServiceInfo
import android.os.Handler
import android.os.IBinder
import android.os.Looper
import dev.motionfusion.app.platform.AppVersion
import dev.motionfusion.app.platform.Foreground
import dev.motionfusion.app.platform.RenewedWakeLock
import android.text.format.DateUtils
import androidx.core.app.NotificationCompat
import androidx.core.app.ServiceCompat
import androidx.core.content.ContextCompat
import dev.motionfusion.app.R
import dev.motionfusion.app.settings.LiveSettings
import dev.motionfusion.app.sensor.SamplingRate
import dev.motionfusion.core.calib.Calibration
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.Continuation
import dev.motionfusion.core.session.RemoteStart
import android.util.Log
import java.io.File
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.Dispatchers
import kotlinx.coroutines.SupervisorJob
import kotlinx.coroutines.cancel
import kotlinx.coroutines.launch

/**
 * Records every sensor stream into a session while the user wants it: a foreground service of
 * type `specialUse` (docs/RECORDING.md), started from the Record button, holding a partial wake lock (non-wake-up
 * sensors deliver with the screen off only under one; it times out unless renewed, so a
 * crashed service cannot keep the phone awake) and an ongoing notification with the elapsed
 * time, the number of samples and a Stop action. It does not depend on any activity: closing
 * the app's screens does not stop it; only Stop (button or notification), a limit of the
 * settings ([RecordingLimits]: maximum duration, battery level, checked once a second on the
 * injected clock) or a storage problem does; a limit or a problem is told to the user.
 *
 * The wake lock is taken when Record is pressed, before anything is prepared. The service is
 * sticky: when the system kills the process during a recording and later restarts the service
 * (a null intent), the recording resumes by itself as a linked continuation — the cut-off session
 * is repaired and a new one, whose meta.json names it and the gap (`continues`), goes on with the
 * same settings, limits and start time ([RecordingInProgress]); the notification and the app say
 * so. A recording the user stopped never resumes: Stop forgets it before anything else.
 *
 * Android 12+ lets the restarted service enter the foreground only when the app is exempt (battery
 * optimisation off for it, among others); otherwise it refuses ([Foreground.Refusal.BACKGROUND]).
 * Then the recording waits for the user: a notification "Recording interrupted — tap to continue"
 * (and the record bar's Continue) starts the service again from the user's tap, which Android
 * allows, and the recording goes on as a linked continuation whose gap ends at the tap.
 */
class RecordingService : Service() {
    private val main = Handler(Looper.getMainLooper())
    private val scope = CoroutineScope(SupervisorJob() + Dispatchers.Main.immediate)
    private lateinit var deps: RecordingDependencies
    private var preparing = false
    private var stopWhenReady = false
    private var holdsCapture = false
    private var recorder: Recorder? = null
    private var session: File? = null
    private var still = false
    private lateinit var wakeLock: RenewedWakeLock
    private var startedElapsedMs = 0L
    private var startedWallMs = 0L
    private var batteryCheckedNs = Long.MIN_VALUE / 2
    private var limits = RecordingLimits()
    /** The earlier session and the gap when this recording resumed one the system killed. */
    private var continues: Continuation? = null

    /** A laptop's remote start of this recording (docs/STREAMING.md, "Remote control"), null when started here. */
    private var remoteStart: RemoteStart? = null
    /** Restarted by the system, resuming (until the recorder runs). */
    private var resuming = false

    private val tick = object : Runnable {
        override fun run() {
            val r = recorder ?: return
            val now = deps.clock.elapsedRealtimeNanos()
            limitReached(now)?.let { end ->
                r.stopBecause(end)
                stopRecording()
                return
            }
            if (ticks++ % NOTIFICATION_UPDATE_TICKS == 0L) updateNotification()
            keepWakeLockAsNeeded()
            main.postDelayed(this, 1_000)
        }
    }

    /** The limit of the settings reached at [nowNs] (elapsed realtime), or null. */
    private fun limitReached(nowNs: Long): RecordingEnd? {
        val max = limits.maxDurationS
        if (max > 0 && nowNs - startedElapsedMs * 1_000_000 >= max * 1_000_000_000) return RecordingEnd.MaxDuration(max)
        if (limits.stopBatteryPercent > 0 && nowNs - batteryCheckedNs >= BATTERY_CHECK_NS) {
            batteryCheckedNs = nowNs
            val b = deps.battery.read()
            val percent = b.percent
            if (!b.charging && percent != null && percent <= limits.stopBatteryPercent) return RecordingEnd.BatteryLow(percent)
        }
        return null
    }

    override fun onCreate() {
        super.onCreate()
        deps = (application as RecordingDependencies.Provider).recordingDependencies
        wakeLock = RenewedWakeLock(this, "MotionFusion:recording", deps.clock)
    }

    override fun onBind(intent: Intent?): IBinder? = null

    override fun onStartCommand(intent: Intent?, flags: Int, startId: Int): Int {
        when (intent?.action) {
            ACTION_STOP -> {
                // Forgotten first: a kill while the session is being finished must not resume it.
                deps.recordingDisk.execute(null) { deps.inProgress.clear() }
                stopRecording()
            }
            ACTION_START -> {
                // A new recording: an interrupted one is no longer offered (its session stays as it is, repaired by the start).
                notificationManager().cancel(INTERRUPTED_NOTIFICATION_ID)
                startRecording(still = intent.getBooleanExtra(EXTRA_STILL, false), remote = remoteStartOf(intent))
            }
            // Restarted by the system after the process died (START_STICKY): the recording resumes if one was running.
            null -> if (recorder == null && !preparing) resumeRecording()
            // The user tapped "tap to continue" (or Continue in the app): the interrupted recording goes on.
            ACTION_CONTINUE -> {
                notificationManager().cancel(INTERRUPTED_NOTIFICATION_ID)
                if (recorder == null && !preparing) resumeRecording()
            }
            else -> if (recorder == null && !preparing) stopSelf()
        }
        return START_STICKY
    }

    /**
     * Foreground and sensors at once (main thread); the disk work (repair of interrupted
     * sessions, which takes seconds after a long killed recording, and the new session's files)
     * on the disk executor, with progress in [Recordings]; then the recorder is attached. The
     * session's settings and calibration are taken once the stores have been read (a Record in
     * the first moments after the process started waits for them; never the defaults instead).
     */
    private fun startRecording(still: Boolean, remote: RemoteStart? = null) {
        if (recorder != null || preparing) return
        remoteStart = remote
        // The wake lock first: a phone pocketed right after Record does not sleep while the recording is prepared.
        holdWakeLock()
        this.still = still
        continues = null
        createChannels()
        startedWallMs = deps.clock.wallClockMs()
        startedElapsedMs = deps.clock.elapsedRealtimeNanos() / 1_000_000
        // Foreground first: startForegroundService() must be answered within a few seconds.
        goForeground()?.let { refusal ->
            notStarted(getString(R.string.record_not_started, getString(refusal.text)), refusal)
            return
        }
        beginPreparing(resuming = false)
        scope.launch {
            deps.awaitStores()
            prepare(still, null)
        }
    }

    /** Foreground refused: told to the user, nothing recorded, the wake lock let go. */
    private fun notStarted(alert: String, refusal: Foreground.Refusal) {
        releaseWakeLock()
        deps.recordings.set(RecordingState.NotStarted(refusal))
        notificationManager().notify(END_NOTIFICATION_ID, alertNotification(alert))
        stopSelf()
    }

    private fun beginPreparing(resuming: Boolean) {
        preparing = true
        stopWhenReady = false
        deps.recordings.set(RecordingState.Preparing(0, 0, resuming))
        deps.capture.acquire()
        holdsCapture = true
    }

    /**
     * The system restarted the service after the process was killed: if a recording was running
     * ([RecordingInProgress]), its cut-off session is repaired (under its folder's lock, on the
     * recording's queue) and the recording goes on in a new session that names it and the gap. On
     * Android 14+ the restart enters the foreground with the manifest's type as a start does.
     * Android 12+ refuses the foreground to a restart in the background unless the app is exempt:
     * then the recording is [interrupted] and waits for the user's tap ([ACTION_CONTINUE], which
     * comes here again; the gap ends at the tap). Another refusal (a permission missing) is told
     * and the recording forgotten; the session before the kill stays as it was written, repaired by
     * the next listing or Record.
     */
    private fun resumeRecording() {
        holdWakeLock()
        createChannels()
        continues = null
        remoteStart = null
        resuming = true
        startedWallMs = deps.clock.wallClockMs()
        startedElapsedMs = deps.clock.elapsedRealtimeNanos() / 1_000_000
        goForeground()?.let { refusal ->
            resuming = false
            releaseWakeLock()
            if (refusal == Foreground.Refusal.BACKGROUND) {
                interrupted()
            } else {
                deps.recordingDisk.execute(null) { deps.inProgress.clear() }
                notStarted(getString(R.string.record_resume_failed, getString(refusal.text)), refusal)
            }
            return
        }
        beginPreparing(resuming = true)
        scope.launch {
            deps.awaitStores()
            val resumedNs = deps.clock.elapsedRealtimeNanos()
            deps.recordingDisk.execute(null) {
                val entry = deps.inProgress.read()
                val previous = resumable(entry, resumedNs)
                if (entry == null || previous == null) {
                    deps.inProgress.clear()
                    main.post { nothingToResume() }
                    return@execute
                }
                val gapStart = try {
                    deps.sessions.locks.withFolder(previous) {
                        if (deps.format.isInterrupted(previous)) deps.format.recover(previous)
                        deps.format.endNs(previous)
                    }
                } catch (e: Exception) {
                    null // unreadable: the gap's start is unknown; the repair is tried again by the next listing
                }
                main.post {
                    if (!preparing) return@post
                    startedWallMs = entry.startedWallMs
                    startedElapsedMs = entry.startedElapsedMs
                    still = entry.still
                    continues = Continuation(previous.name, gapStart, resumedNs)
                    prepare(entry.still, entry.limits)
                }
            }
        }
    }

    /**
     * Disk queue: the session folder of [entry] when the recording can go on at [nowNs]; null when
     * there is nothing to resume: none was running (stopped by the user), its session is gone, or the
     * phone restarted since (another clock).
     */
    private fun resumable(entry: RecordingInProgress.Entry?, nowNs: Long): File? {
        if (entry == null || entry.startedElapsedMs * 1_000_000 > nowNs) return null
        return deps.sessions.folder(entry.session).takeIf { it.isDirectory }
    }

    /**
     * Main thread, the foreground refused to a restart in the background (Android 12+): when a
     * recording was running, the user is offered to continue it (a notification whose tap starts
     * [ACTION_CONTINUE], and the app's [RecordingState.Interrupted]); its entry is kept for that.
     * Nothing is recorded meanwhile; the service stops.
     */
    private fun interrupted() {
        val nowNs = deps.clock.elapsedRealtimeNanos()
        deps.recordingDisk.execute(null) {
            val entry = deps.inProgress.read()
            val previous = resumable(entry, nowNs)
            if (previous == null) deps.inProgress.clear()
            main.post {
                if (previous != null) {
                    Log.i("RecordingService", "restart refused the foreground: recording ${previous.name} waits for the user")
                    deps.recordings.set(RecordingState.Interrupted(previous.name))
                    notificationManager().notify(INTERRUPTED_NOTIFICATION_ID, interruptedNotification())
                }
                stopSelf()
            }
        }
    }

    /** A restart with no recording to resume: back to idle, the foreground and the wake lock let go. */
    private fun nothingToResume() {
        preparing = false
        resuming = false
        if (holdsCapture) deps.capture.release()
        holdsCapture = false
        releaseWakeLock()
        if (deps.recordings.state.value is RecordingState.Preparing) deps.recordings.set(RecordingState.Idle)
        ServiceCompat.stopForeground(this, ServiceCompat.STOP_FOREGROUND_REMOVE)
        stopSelf()
    }

    /**
     * Main thread, the stores read: the session's settings, sensors and calibration; then its files
     * on the recording's disk queue. [resumedLimits]: the limits of the recording being resumed.
     */
    private fun prepare(still: Boolean, resumedLimits: RecordingLimits?) {
        val capture = deps.capture
        // A still recording: the streams it writes, as fast as the device delivers.
        val live = deps.settings.value.let { if (still) it.copy(rate = SamplingRate.Delay.FASTEST) else it }
        // The still recording asks for 1–3 h (docs/CALIBRATION.md): the user's limits are for ordinary recordings.
        limits = resumedLimits ?: if (still) RecordingLimits.STILL else live.limits
        batteryCheckedNs = Long.MIN_VALUE / 2
        val filterSettings = capture.filterSettingsFor(live)
        val sensors = if (still) capture.sensors.filterKeys { it in STILL_STREAMS } else capture.sensors
        // The calibration the live filter applies during the recording, and what meta.json says of it.
        val stored = deps.sessionCalibration()
        val applied = if (stored?.appliedInLiveFilter == true) capture.calibrationFor(stored.calibration) else null
        val calibration = stored?.copy(appliedInLiveFilter = applied != null)
        val rate = live.rate
        // The latency the recording's listener is registered with (it stays registered so while the recording runs).
        val latencyUs = capture.reportLatencyUsFor(rate, if (still) STILL_STREAMS else null)
        val wakeLockUse = capture.wakeLockUseFor(rate, if (still) STILL_STREAMS else null) // the case keepWakeLockAsNeeded() meets
        val continues = continues
        // A resumed part is anchored and named at its own start.
        val nowWallMs = if (continues != null) deps.clock.wallClockMs() else startedWallMs
        val anchor = ClockAnchor(nowWallMs, deps.clock.elapsedRealtimeNanos())
        val version = AppVersion.of(this)
        val entry = { dir: File -> RecordingInProgress.Entry(dir.name, still, startedWallMs, startedElapsedMs, limits) }
        deps.recordingDisk.execute(null) {
            val sessions = deps.sessions
            sessions.repairInterrupted { done, total -> main.post { if (preparing) deps.recordings.set(RecordingState.Preparing(done, total, continues != null)) } }
            var dir: File? = null
            try {
                val d = sessions.newRecording(nowWallMs)
                dir = d
                val metadata = RecordingMetadata.create(
                    version,
                    sensors, rate, latencyUs,
                    filterSettings,
                    anchor,
                    calibration,
                    still,
                    wakeLockUse,
                ).copy(continues = continues, remoteStart = remoteStart.takeIf { continues == null })
                val sink = deps.format.create(d, metadata)
                try {
                    deps.inProgress.write(entry(d))
                } catch (e: Exception) {
                    // The recording goes on; only its resumption after a kill is lost.
                    Log.w("RecordingService", "cannot keep the recording in progress: ${e.message}")
                }
                main.post { ready(d, sink, live, applied, still) }
            } catch (e: Exception) {
                Log.e("RecordingService", "cannot create the session", e)
                val failed = RecorderResult(RecordingEnd.WriteFailed(e.message ?: e.javaClass.simpleName), LongArray(SessionStream.entries.size), 0)
                main.post { ended(dir, failed) }
            }
        }
    }

    /** Main thread: the session exists; the recorder joins the capture. */
    private fun ready(dir: File, sink: SessionSink, live: LiveSettings, calibration: Calibration?, still: Boolean) {
        preparing = false
        resuming = false
        val minFree = deps.minFreeBytes
        val recorder = Recorder(
            sink,
            onEnd = { result -> onWriterEnded(dir, result) },
            freeBytes = { dir.usableSpace },
            minFreeBytes = minFree,
            anchorNow = RecordingMetadata::anchorNow,
            streams = if (still) STILL_STREAMS else null,
            notBeforeNs = remoteStart?.takeIf { continues == null }?.elapsedRealtimeNs ?: Long.MIN_VALUE,
        )
        this.recorder = recorder
        this.session = dir
        deps.recordings.set(
            RecordingState.Active(
                dir, startedElapsedMs, { recorder.rowCount }, { recorder.markers },
                recorder::mark, limits, still, deps.capture.sensors.keys.count { !still || it in STILL_STREAMS }, continues,
                recorder::clockExchange,
            ),
        )
        deps.capture.attach(recorder, live, calibration, if (still) STILL_STREAMS else null)
        keepWakeLockAsNeeded()
        main.post(tick)
        if (stopWhenReady) stopRecording()
    }

    /** The partial wake lock, from the press of Record (or the restart) to the end; renewed every minute while recording. */
    private fun holdWakeLock() = wakeLock.hold()

    /**
     * While recording, the wake lock only where the sensors registered cannot wake the phone for their batches
     * themselves ([dev.motionfusion.app.sensor.WakeLockNeed]); renewed every minute while held.
     */
    private fun keepWakeLockAsNeeded() {
        when {
            !deps.capture.wakeLockNeed.held -> releaseWakeLock()
            wakeLock.isHeld -> wakeLock.renewIfDue()
            else -> holdWakeLock()
        }
    }

    private fun releaseWakeLock() = wakeLock.release()

    /** Enters the foreground, as a `specialUse` service on Android 14+; returns why the system refused, or null ([Foreground.enter]). */
    private fun goForeground(): Foreground.Refusal? =
        Foreground.enter(this, NOTIFICATION_ID, ongoingNotification(), FOREGROUND_SERVICE_TYPE, deps::startForeground)

    /** Stop button or notification action: the capture hands the recorder everything up to now, then it finishes. */
    private fun stopRecording() {
        val r = recorder
        if (r == null) {
            if (preparing) stopWhenReady = true else stopSelf()
            return
        }
        deps.capture.detach(r)
    }

    /** Capture thread: the recording is over (stopped or failed). Repairs a failed session off the main thread, then hands over to main. */
    private fun onWriterEnded(dir: File, result: RecorderResult) {
        if (result.end is RecordingEnd.WriteFailed) {
            deps.recordingDisk.execute(dir) {
                try {
                    deps.sessions.recordingEnded(dir)
                    if (deps.format.isInterrupted(dir)) deps.format.recover(dir)
                } catch (_: Exception) {
                    // Still interrupted: the next start's repair tries again.
                }
                main.post { ended(dir, result) }
            }
        } else {
            main.post { ended(dir, result) }
        }
    }

    private fun ended(dir: File?, result: RecorderResult) {
        // The user reads what kind of failure it was (endMessage); the system's words go to the log.
        (result.end as? RecordingEnd.WriteFailed)?.let { Log.e("RecordingService", "recording ${dir?.name} stopped: writing failed: ${it.message}") }
        preparing = false
        resuming = false
        recorder = null
        session = null
        if (dir != null) deps.sessions.recordingEnded(dir)
        if (holdsCapture) deps.capture.release()
        holdsCapture = false
        main.removeCallbacks(tick)
        releaseWakeLock()
        // Ended, however: nothing to resume.
        deps.recordingDisk.execute(null) { deps.inProgress.clear() }
        deps.recordings.set(RecordingState.Ended(dir, result, still))
        ServiceCompat.stopForeground(this, ServiceCompat.STOP_FOREGROUND_REMOVE)
        if (result.end != RecordingEnd.Stopped) notificationManager().notify(END_NOTIFICATION_ID, alertNotification(endMessage(this, result), result.end.isFailure))
        stopSelf()
    }

    override fun onDestroy() {
        // The system destroys a stopped service only after ended(); if it happens while
        // recording (it should not), finish what is queued rather than leave it open.
        if (recorder != null) stopRecording()
        main.removeCallbacks(tick)
        scope.cancel()
        super.onDestroy()
    }

    private fun notificationManager() = getSystemService(NotificationManager::class.java)

    private fun createChannels() = Foreground.createChannels(this)

    /** Ticks of the recording so far (the notification is updated every [NOTIFICATION_UPDATE_TICKS]). */
    private var ticks = 0L

    /** The ongoing notification's builder: made once with its PendingIntents; an update only sets the text. */
    private var ongoing: NotificationCompat.Builder? = null

    /** Notifications posted by the updates (for tests: a few a minute, not one a second). */
    internal var notificationUpdates = 0
        private set

    private fun updateNotification() {
        notificationUpdates++
        notificationManager().notify(NOTIFICATION_ID, ongoingNotification())
    }

    private fun ongoingNotification(): Notification {
        val elapsedS = if (startedElapsedMs == 0L) 0 else (deps.clock.elapsedRealtimeNanos() / 1_000_000 - startedElapsedMs) / 1000
        val rows = recorder?.rowCount ?: 0L
        val builder = ongoing ?: NotificationCompat.Builder(this, CHANNEL_RECORDING)
            .setSmallIcon(R.drawable.ic_record)
            .setContentTitle(getString(R.string.record_notification_title))
            .setOngoing(true)
            .setOnlyAlertOnce(true)
            .setShowWhen(true)
            .setUsesChronometer(true)
            .setCategory(NotificationCompat.CATEGORY_SERVICE)
            .setForegroundServiceBehavior(NotificationCompat.FOREGROUND_SERVICE_IMMEDIATE)
            .setContentIntent(openApp())
            .addAction(
                0, getString(R.string.record_stop),
                PendingIntent.getService(this, 1, Intent(this, RecordingService::class.java).setAction(ACTION_STOP), PendingIntent.FLAG_IMMUTABLE or PendingIntent.FLAG_UPDATE_CURRENT),
            )
            .also { ongoing = it }
        // The chronometer counts the time on the shade by itself; the text's time and count are as of this update.
        return builder
            .setWhen(startedWallMs)
            .setContentText(getString(R.string.record_notification_text, DateUtils.formatElapsedTime(elapsedS), rows))
            // A resumed recording says so (the state changes from resuming to resumed, so it is set on every update).
            .setSubText(continues?.let { getString(R.string.record_resumed_short, gapText(it)) } ?: if (resuming) getString(R.string.record_resuming) else null)
            .build()
    }

    private fun alertNotification(text: String, failed: Boolean = true): Notification =
        NotificationCompat.Builder(this, CHANNEL_ALERTS)
            .setSmallIcon(R.drawable.ic_record)
            .setContentTitle(getString(if (failed) R.string.record_failed_title else R.string.record_limit_title))
            .setContentText(text)
            .setStyle(NotificationCompat.BigTextStyle().bigText(text))
            .setAutoCancel(true)
            .setContentIntent(openApp())
            .build()

    /** "Recording interrupted — tap to continue": the tap starts the service in the foreground, which Android 12+ allows from a notification. */
    private fun interruptedNotification(): Notification {
        val text = getString(R.string.record_interrupted_text)
        return NotificationCompat.Builder(this, CHANNEL_ALERTS)
            .setSmallIcon(R.drawable.ic_record)
            .setContentTitle(getString(R.string.record_interrupted_title))
            .setContentText(text)
            .setStyle(NotificationCompat.BigTextStyle().bigText(text))
            .setAutoCancel(true)
            .setCategory(NotificationCompat.CATEGORY_ERROR)
            .setContentIntent(continueIntent(this))
            .build()
    }

    /** The app's launcher screen (the live screen), named by the manifest rather than by class: record does not depend on the screens. */
    private fun openApp(): PendingIntent = PendingIntent.getActivity(
        this, 0,
        (packageManager.getLaunchIntentForPackage(packageName) ?: Intent().setPackage(packageName)).addFlags(Intent.FLAG_ACTIVITY_SINGLE_TOP),
        PendingIntent.FLAG_IMMUTABLE,
    )


    companion object {
        internal const val ACTION_START = "dev.motionfusion.app.record.START"
        internal const val ACTION_STOP = "dev.motionfusion.app.record.STOP"
        internal const val ACTION_CONTINUE = "dev.motionfusion.app.record.CONTINUE"
        internal const val NOTIFICATION_ID = 7001
        internal const val END_NOTIFICATION_ID = 7002
        internal const val INTERRUPTED_NOTIFICATION_ID = 7003
        internal const val CHANNEL_RECORDING = Foreground.CHANNEL_RECORDING
        internal const val CHANNEL_ALERTS = Foreground.CHANNEL_ALERTS
        internal const val EXTRA_STILL = "dev.motionfusion.app.record.STILL"

        /** A laptop's remote start ([RemoteStart]): who, its clock's name, its instant on that clock and on the sensor clock. */
        internal const val EXTRA_REMOTE_BY = "dev.motionfusion.app.record.REMOTE_BY"
        internal const val EXTRA_REMOTE_CLOCK = "dev.motionfusion.app.record.REMOTE_CLOCK"
        internal const val EXTRA_REMOTE_LAPTOP_NS = "dev.motionfusion.app.record.REMOTE_LAPTOP_NS"
        internal const val EXTRA_REMOTE_AT_NS = "dev.motionfusion.app.record.REMOTE_AT_NS"

        /** The remote start an [ACTION_START] carries, or null (Record pressed on the phone). */
        internal fun remoteStartOf(intent: Intent): RemoteStart? {
            val by = intent.getStringExtra(EXTRA_REMOTE_BY) ?: return null
            return RemoteStart(by, intent.getStringExtra(EXTRA_REMOTE_CLOCK), intent.getLongExtra(EXTRA_REMOTE_LAPTOP_NS, 0L), intent.getLongExtra(EXTRA_REMOTE_AT_NS, 0L))
        }

        /** Starts a recording as Record does, for a laptop in control: tagged with [remote] (meta.json's remote_start). */
        fun startRemote(context: Context, remote: RemoteStart): Foreground.Refusal? = startForeground(
            context,
            Intent(context, RecordingService::class.java).setAction(ACTION_START)
                .putExtra(EXTRA_REMOTE_BY, remote.by).putExtra(EXTRA_REMOTE_CLOCK, remote.laptopClock)
                .putExtra(EXTRA_REMOTE_LAPTOP_NS, remote.laptopNs).putExtra(EXTRA_REMOTE_AT_NS, remote.elapsedRealtimeNs),
        )

        /**
         * What a still recording writes: the streams `fusion allan` reads (accelerometer and
         * gyroscope, calibrated and uncalibrated) and the magnetometers, so that its
         * orientation.csv replays; not the phone's rotation vectors.
         */
        internal val STILL_STREAMS: Set<SessionStream> = setOf(
            SessionStream.ACCELEROMETER, SessionStream.ACCELEROMETER_UNCALIBRATED, SessionStream.GYROSCOPE, SessionStream.GYROSCOPE_UNCALIBRATED,
            SessionStream.MAGNETOMETER, SessionStream.MAGNETOMETER_UNCALIBRATED,
        )

        /** The ongoing notification's text is updated every 5 ticks (5 s): the chronometer shows the time meanwhile. */
        internal const val NOTIFICATION_UPDATE_TICKS = 5L

        /** The wake lock times out after 10 minutes unless renewed, every minute while recording ([RenewedWakeLock]). */
        internal const val WAKE_LOCK_TIMEOUT_MS = RenewedWakeLock.TIMEOUT_MS
        internal const val WAKE_LOCK_RENEW_NS = RenewedWakeLock.RENEW_NS

        /** The battery level is read every 30 s (it changes slowly). */
        private const val BATTERY_CHECK_NS = 30_000_000_000L

        /** The manifest's android:foregroundServiceType; its permission is FOREGROUND_SERVICE_SPECIAL_USE (ForegroundServiceTest). */
        internal const val FOREGROUND_SERVICE_TYPE = ServiceInfo.FOREGROUND_SERVICE_TYPE_SPECIAL_USE

        /**
         * Starts a recording ([still]: a still recording, docs/CALIBRATION.md); call from a user action (Android 12+ forbids it from the background).
         * Returns why the system refused to start the service, or null.
         */
        fun start(context: Context, still: Boolean = false): Foreground.Refusal? =
            startForeground(context, Intent(context, RecordingService::class.java).setAction(ACTION_START).putExtra(EXTRA_STILL, still))

        /** Continues an [RecordingState.Interrupted] recording in a linked session; from a user action, as [start]. */
        fun continueRecording(context: Context): Foreground.Refusal? =
            startForeground(context, Intent(context, RecordingService::class.java).setAction(ACTION_CONTINUE))

        private fun startForeground(context: Context, intent: Intent): Foreground.Refusal? = try {
            ContextCompat.startForegroundService(context, intent)
            null
        } catch (e: IllegalStateException) {
            Foreground.Refusal.of(e, "RecordingService")
        }

        /** The tap of the interrupted notification: the service, started in the foreground ([ACTION_CONTINUE]). */
        internal fun continueIntent(context: Context): PendingIntent = PendingIntent.getForegroundService(
            context, 2, Intent(context, RecordingService::class.java).setAction(ACTION_CONTINUE),
            PendingIntent.FLAG_IMMUTABLE or PendingIntent.FLAG_UPDATE_CURRENT,
        )

        fun stop(context: Context) {
            context.startService(Intent(context, RecordingService::class.java).setAction(ACTION_STOP))
        }

        /** The gap of a resumed recording, "0:42"; "—" when the earlier part had no sample. */
        internal fun gapText(c: Continuation): String = Formats.gap(c.gapNs)

        /** What to tell the user about how a recording ended. */
        internal fun endMessage(context: Context, result: RecorderResult): String {
            val rows = result.rows
            return when (val e = result.end) {
                RecordingEnd.Stopped -> context.getString(R.string.record_end_stopped, rows)
                is RecordingEnd.MaxDuration -> context.getString(R.string.record_end_max_duration, DateUtils.formatElapsedTime(e.seconds), rows)
                is RecordingEnd.BatteryLow -> context.getString(R.string.record_end_battery_low, e.percent, rows)
                is RecordingEnd.QueueOverflow -> context.getString(R.string.record_end_overflow, rows)
                is RecordingEnd.StorageLow -> context.getString(R.string.record_end_storage_low, rows, e.freeBytes / (1024 * 1024))
                is RecordingEnd.WriteFailed -> context.getString(R.string.record_end_write_failed, rows)
            }
        }
    }
}
