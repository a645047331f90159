package dev.motionfusion.app.record

import android.content.Context
import android.os.Handler
import android.os.Looper
import android.util.Log
import dev.motionfusion.app.R
import dev.motionfusion.app.platform.AppVersion
import dev.motionfusion.app.platform.Foreground
import dev.motionfusion.app.platform.ForegroundLifecycle
import dev.motionfusion.app.sensor.SamplingRate
import dev.motionfusion.app.settings.LiveSettings
import dev.motionfusion.app.settings.RecordingLimits
import dev.motionfusion.core.calib.Calibration
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.Continuation
import dev.motionfusion.core.session.RemoteStart
import java.io.File
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.Dispatchers
import kotlinx.coroutines.SupervisorJob
import kotlinx.coroutines.cancel
import kotlinx.coroutines.launch

/**
 * One recording from Record (or the restart that resumes it) to its end, as [RecordingService] coordinates it
 * (docs/RECORDING.md): the wake lock from the press of Record, the foreground ([foreground]), the session's files
 * prepared on the recording's disk queue, the recorder attached to the capture, a tick once a second on the injected
 * clock (the limits, [RecordingLimitWatch]; the notification's text, [notifications]; the wake lock as the sensors need
 * it), and the end: the session finished or repaired, the user told, the service stopped. A restart resumes the
 * recording that was running ([RecordingResumption]), or offers to continue it when Android 12+ refuses the foreground.
 * Main thread.
 */
internal class RecordingLifecycle(
    private val context: Context,
    private val deps: RecordingDependencies,
    private val foreground: ForegroundLifecycle,
    private val notifications: RecordingNotifications,
) {
    private val main = Handler(Looper.getMainLooper())
    private val scope = CoroutineScope(SupervisorJob() + Dispatchers.Main.immediate)
    private val resumption = RecordingResumption(deps)
    private var preparing = false
    private var stopWhenReady = false
    private var holdsCapture = false
    private var recorder: Recorder? = null
    private var still = false
    private var startedElapsedMs = 0L
    private var startedWallMs = 0L
    private var limits = RecordingLimits()
    private var limitWatch: RecordingLimitWatch? = null

    /** The earlier session and the gap when this recording resumed one the system killed. */
    private var continues: Continuation? = null

    /** A laptop's remote start of this recording (docs/STREAMING.md, "Remote control"), null when started here. */
    private var remoteStart: RemoteStart? = null

    /** Restarted by the system, resuming (until the recorder runs). */
    private var resuming = false

    /** Ticks of the recording so far (the notification is updated every [RecordingService.NOTIFICATION_UPDATE_TICKS]). */
    private var ticks = 0L

    /** Notifications posted by the updates (for tests: a few a minute, not one a second). */
    var notificationUpdates = 0
        private set

    /** Neither recording nor preparing one. */
    val idle: Boolean get() = recorder == null && !preparing

    private val tick = object : Runnable {
        override fun run() {
            val r = recorder ?: return
            limitWatch?.reached(deps.clock.elapsedRealtimeNanos())?.let { end ->
                r.stopBecause(end)
                stop()
                return
            }
            if (ticks++ % RecordingService.NOTIFICATION_UPDATE_TICKS == 0L) {
                notificationUpdates++
                foreground.notify(ongoingNotification())
            }
            keepWakeLockAsNeeded()
            main.postDelayed(this, 1_000)
        }
    }

    /**
     * Foreground and sensors at once (main thread); the disk work (repair of interrupted sessions, which takes seconds
     * after a long killed recording, and the new session's files) on the disk executor, with progress in
     * [Recordings]; then the recorder is attached. The session's settings and calibration are taken once the stores
     * have been read (a Record in the first moments after the process started waits for them; never the defaults instead).
     */
    fun start(still: Boolean, remote: RemoteStart?) {
        if (!idle) return
        remoteStart = remote
        // The wake lock first: a phone pocketed right after Record does not sleep while the recording is prepared.
        foreground.holdWakeLock()
        this.still = still
        continues = null
        startedWallMs = deps.clock.wallClockMs()
        startedElapsedMs = deps.clock.elapsedRealtimeNanos() / 1_000_000
        // Foreground first: startForegroundService() must be answered within a few seconds.
        foreground.enter(ongoingNotification())?.let { refusal ->
            notStarted(context.getString(R.string.record_not_started, context.getString(refusal.text)), refusal)
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
        deps.recordings.set(RecordingState.NotStarted(refusal))
        foreground.notify(notifications.alert(alert), RecordingService.END_NOTIFICATION_ID)
        foreground.leave()
    }

    private fun beginPreparing(resuming: Boolean) {
        preparing = true
        stopWhenReady = false
        deps.recordings.set(RecordingState.Preparing(0, 0, resuming))
        deps.capture.acquire()
        holdsCapture = true
    }

    /**
     * The system restarted the service after the process was killed (or the user tapped to continue): if a recording
     * was running ([RecordingInProgress]), its cut-off session is repaired (under its folder's lock, on the recording's
     * queue) and the recording goes on in a new session that names it and the gap. On Android 14+ the restart enters
     * the foreground with the manifest's type as a start does. Android 12+ refuses the foreground to a restart in the
     * background unless the app is exempt: then the recording is [interrupted] and waits for the user's tap
     * ([RecordingService.ACTION_CONTINUE], which comes here again; the gap ends at the tap). Another refusal (a
     * permission missing) is told and the recording forgotten; the session before the kill stays as it was written,
     * repaired by the next listing or Record.
     */
    fun resume() {
        foreground.holdWakeLock()
        continues = null
        remoteStart = null
        resuming = true
        startedWallMs = deps.clock.wallClockMs()
        startedElapsedMs = deps.clock.elapsedRealtimeNanos() / 1_000_000
        foreground.enter(ongoingNotification())?.let { refusal ->
            resuming = false
            foreground.releaseWakeLock()
            if (refusal == Foreground.Refusal.BACKGROUND) {
                interrupted()
            } else {
                deps.recordingDisk.execute(null) { deps.inProgress.clear() }
                notStarted(context.getString(R.string.record_resume_failed, context.getString(refusal.text)), refusal)
            }
            return
        }
        beginPreparing(resuming = true)
        scope.launch {
            deps.awaitStores()
            val resumedNs = deps.clock.elapsedRealtimeNanos()
            deps.recordingDisk.execute(null) {
                val resume = resumption.resume(resumedNs)
                main.post {
                    if (resume == null) return@post nothingToResume()
                    if (!preparing) return@post
                    startedWallMs = resume.entry.startedWallMs
                    startedElapsedMs = resume.entry.startedElapsedMs
                    still = resume.entry.still
                    continues = resume.continues
                    prepare(resume.entry.still, resume.entry.limits)
                }
            }
        }
    }

    /**
     * Main thread, the foreground refused to a restart in the background (Android 12+): when a recording was running,
     * the user is offered to continue it (a notification whose tap starts [RecordingService.ACTION_CONTINUE], and the
     * app's [RecordingState.Interrupted]); its entry is kept for that. Nothing is recorded meanwhile; the service stops.
     */
    private fun interrupted() {
        val nowNs = deps.clock.elapsedRealtimeNanos()
        deps.recordingDisk.execute(null) {
            val previous = resumption.waiting(nowNs)
            main.post {
                if (previous != null) {
                    Log.i("RecordingService", "restart refused the foreground: recording ${previous.name} waits for the user")
                    deps.recordings.set(RecordingState.Interrupted(previous.name))
                    foreground.notify(notifications.interrupted(), RecordingService.INTERRUPTED_NOTIFICATION_ID)
                }
                foreground.leave()
            }
        }
    }

    /** A restart with no recording to resume: back to idle, the foreground and the wake lock let go. */
    private fun nothingToResume() {
        preparing = false
        resuming = false
        if (holdsCapture) deps.capture.release()
        holdsCapture = false
        if (deps.recordings.state.value is RecordingState.Preparing) deps.recordings.set(RecordingState.Idle)
        foreground.leave()
    }

    /**
     * Main thread, the stores read: the session's settings, sensors and calibration; then its files on the recording's
     * disk queue. [resumedLimits]: the limits of the recording being resumed.
     */
    private fun prepare(still: Boolean, resumedLimits: RecordingLimits?) {
        val capture = deps.capture
        // A still recording: the streams it writes, as fast as the device delivers.
        val live = deps.settings.value.let { if (still) it.copy(rate = SamplingRate.Delay.FASTEST) else it }
        // The still recording asks for 1–3 h (docs/CALIBRATION.md): the user's limits are for ordinary recordings.
        limits = resumedLimits ?: if (still) RecordingLimits.STILL else live.limits
        limitWatch = RecordingLimitWatch(limits, startedElapsedMs, deps.battery)
        val filterSettings = capture.filterSettingsFor(live)
        val streams = if (still) RecordingService.STILL_STREAMS else null
        val sensors = if (still) capture.sensors.filterKeys { it in RecordingService.STILL_STREAMS } else capture.sensors
        // The calibration the live filter applies during the recording, and what meta.json says of it.
        val stored = deps.sessionCalibration()
        val applied = if (stored?.appliedInLiveFilter == true) capture.calibrationFor(stored.calibration) else null
        val calibration = stored?.copy(appliedInLiveFilter = applied != null)
        val rate = live.rate
        // The latency the recording's listener is registered with (it stays registered so while the recording runs).
        val latencyUs = capture.reportLatencyUsFor(rate, streams)
        val continues = continues
        // A resumed part is anchored and named at its own start.
        val nowWallMs = if (continues != null) deps.clock.wallClockMs() else startedWallMs
        val anchor = ClockAnchor(nowWallMs, deps.clock.elapsedRealtimeNanos())
        val version = AppVersion.of(context)
        val entry = { dir: File -> RecordingInProgress.Entry(dir.name, still, startedWallMs, startedElapsedMs, limits) }
        val remoteStart = remoteStart
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
        val streams = if (still) RecordingService.STILL_STREAMS else null
        val recorder = Recorder(
            sink,
            onEnd = { result -> onWriterEnded(dir, result) },
            freeBytes = { dir.usableSpace },
            minFreeBytes = deps.minFreeBytes,
            anchorNow = RecordingMetadata::anchorNow,
            streams = streams,
            notBeforeNs = remoteStart?.takeIf { continues == null }?.elapsedRealtimeNs ?: Long.MIN_VALUE,
        )
        this.recorder = recorder
        deps.recordings.set(
            RecordingState.Active(
                dir, startedElapsedMs, { recorder.rowCount }, { recorder.markers },
                recorder::mark, limits, still, deps.capture.sensors.keys.count { streams == null || it in streams }, continues,
                recorder::clockExchange,
            ),
        )
        deps.capture.attach(recorder, live, calibration, streams)
        keepWakeLockAsNeeded()
        main.post(tick)
        if (stopWhenReady) stop()
    }

    /**
     * While recording, the wake lock only where the sensors registered cannot wake the phone for their batches
     * themselves ([dev.motionfusion.app.sensor.WakeLockNeed]); renewed every minute while held. The one place the
     * recording decides on its wake lock.
     */
    private fun keepWakeLockAsNeeded() = foreground.keepWakeLock(deps.capture.wakeLockNeed.held)

    /** Stop (button, notification, a limit): the capture hands the recorder everything up to now, then it finishes. */
    fun stop() {
        val r = recorder
        if (r == null) {
            if (preparing) stopWhenReady = true else foreground.leave()
            return
        }
        deps.capture.detach(r)
    }

    /** Stopped by the user: forgotten first (a kill while the session is being finished must not resume it), then [stop]. */
    fun stopByUser() {
        deps.recordingDisk.execute(null) { deps.inProgress.clear() }
        stop()
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
        if (dir != null) deps.sessions.recordingEnded(dir)
        if (holdsCapture) deps.capture.release()
        holdsCapture = false
        main.removeCallbacks(tick)
        foreground.releaseWakeLock()
        // Ended, however: nothing to resume.
        deps.recordingDisk.execute(null) { deps.inProgress.clear() }
        deps.recordings.set(RecordingState.Ended(dir, result, still))
        if (result.end != RecordingEnd.Stopped) {
            foreground.notify(notifications.alert(RecordingService.endMessage(context, result), result.end.isFailure), RecordingService.END_NOTIFICATION_ID)
        }
        foreground.leave()
    }

    /** The service is destroyed: if it happens while recording (it should not), what is queued is finished rather than left open. */
    fun destroy() {
        if (recorder != null) stop()
        main.removeCallbacks(tick)
        scope.cancel()
    }

    private fun ongoingNotification() = notifications.ongoing(startedWallMs, startedElapsedMs, recorder?.rowCount ?: 0L, continues, resuming)
}
