package dev.motionfusion.app.record

import dev.motionfusion.app.settings.RecordingLimits
import android.app.Notification
import android.app.Service
import android.content.Context
import dev.motionfusion.app.R
import dev.motionfusion.app.platform.Foreground
import dev.motionfusion.app.fusion.Capture
import dev.motionfusion.app.settings.LiveSettings
import dev.motionfusion.app.platform.Clock
import dev.motionfusion.app.platform.DiskExecutor
import dev.motionfusion.app.sessions.SessionsRepository
import dev.motionfusion.core.session.Continuation
import dev.motionfusion.core.session.Marker
import dev.motionfusion.core.session.SessionCalibration
import java.io.File
import kotlinx.coroutines.flow.MutableStateFlow
import kotlinx.coroutines.flow.StateFlow
import kotlinx.coroutines.flow.asStateFlow

/**
 * The recording state, for screens to show: the live screen's record bar and every other
 * screen's [RecordingBanner] render it, the notification says it outside the app.
 */
sealed interface RecordingState {
    data object Idle : RecordingState

    /**
     * Record was pressed: interrupted sessions are being repaired ([repaired] of [toRepair]) and the new one created;
     * [resuming]: the system restarted the service after the recording's process was killed, and the recording resumes.
     */
    data class Preparing(val repaired: Int, val toRepair: Int, val resuming: Boolean = false) : RecordingState

    data class Active(
        val session: File,
        /** `SystemClock.elapsedRealtime()` when recording started, ms. */
        val startedElapsedMs: Long,
        val rows: () -> Long,
        /** Markers set so far. */
        val markers: () -> List<Marker> = { emptyList() },
        /** Sets a marker at a time (sensor clock, ns) with a label (may be empty). */
        val mark: (Long, String) -> Unit = { _, _ -> },
        /** The limits this recording stops at. */
        val limits: RecordingLimits = RecordingLimits(),
        /** A still recording (accelerometer and gyroscope at the fastest rate, for `fusion allan`). */
        val still: Boolean = false,
        /** How many sensor streams are recorded (0: not told). */
        val streams: Int = 0,
        /** This part resumed a recording whose process was killed: the earlier session and the gap; null: not resumed. */
        val continues: Continuation? = null,
        /** Takes a whole clock exchange with a laptop clock while linked, for the session's clock.csv. */
        val clockExchange: (dev.motionfusion.core.sync.ClockExchange, String) -> Unit = { _, _ -> },
    ) : RecordingState {
        /** Whole seconds recorded at [nowElapsedMs] (`SystemClock.elapsedRealtime()`). */
        fun elapsedS(nowElapsedMs: Long): Long = ((nowElapsedMs - startedElapsedMs) / 1000).coerceAtLeast(0)
    }

    data class Ended internal constructor(val session: File?, internal val result: RecorderResult, val still: Boolean = false) : RecordingState

    /** The system refused to start the recording (no foreground service allowed now, a permission missing). */
    data class NotStarted(val refusal: Foreground.Refusal) : RecordingState {
        /** What the screens say: "Recording could not start: " and the refusal's words. */
        fun text(c: Context): String = c.getString(R.string.record_not_started, c.getString(refusal.text))
    }

    /**
     * Android 12+ refused the foreground to the service the system restarted after killing the
     * recording's process: [session], the part before, is kept, and a notification (or the record
     * bar's Continue) continues the recording in a linked session once the user asks.
     */
    data class Interrupted(val session: String) : RecordingState
}

/** The process's recording state: written by [RecordingService] on the main thread, read by anyone. */
class Recordings {
    private val flow = MutableStateFlow<RecordingState>(RecordingState.Idle)
    val state: StateFlow<RecordingState> = flow.asStateFlow()

    val isRecording: Boolean get() = state.value.let { it is RecordingState.Active || it is RecordingState.Preparing }

    /** Record's start delay, counting down before the recording service is started. */
    val countdown = StartCountdown()

    /** Sets a marker at [timestampNs] (sensor clock) with [label] in the recording, if one is running; false otherwise. */
    fun mark(timestampNs: Long, label: String): Boolean {
        val s = state.value as? RecordingState.Active ?: return false
        s.mark(timestampNs, label)
        return true
    }

    internal fun set(s: RecordingState) {
        flow.value = s
    }
}

/** What the recording service needs, from the application's object graph. */
internal interface RecordingDependencies {
    val capture: Capture
    val recordings: Recordings
    val sessions: SessionsRepository
    val format: SessionFormat
    /** The recording's own disk queue (nothing of the screens waits in it). */
    val recordingDisk: DiskExecutor

    /** The recording in progress, kept on storage for a resumption after the process was killed. */
    val inProgress: RecordingInProgress
    val clock: Clock
    /** The user's settings, the recording limits among them. */
    val settings: StateFlow<LiveSettings>

    /** Waits until the settings and the stored calibration have been read from storage (at once once they have). */
    suspend fun awaitStores()

    /** The battery level and charging state. */
    val battery: BatterySource

    /** True once the user answered the notification-permission explanation (asked once, before the first recording). */
    val notificationsAnswered: Boolean

    /** Remembers that the user answered it. */
    fun setNotificationsAnswered()
    /** The phone's stored calibration and whether the user chose it for the live filter, for meta.json; null: none. */
    fun sessionCalibration(): SessionCalibration?

    /** Recording stops cleanly when free space falls below this. */
    val minFreeBytes: Long

    /** Enters the foreground (ServiceCompat.startForeground); tests make it refuse as the system can. */
    fun startForeground(service: Service, id: Int, notification: Notification, type: Int)

    /** Implemented by the application. */
    interface Provider {
        val recordingDependencies: RecordingDependencies
    }
}
