package dev.motionfusion.app.record

import android.app.Service
import android.content.Context
import android.content.Intent
import android.content.pm.ServiceInfo
import android.os.IBinder
import android.text.format.DateUtils
import dev.motionfusion.app.R
import dev.motionfusion.app.platform.Foreground
import dev.motionfusion.app.platform.ForegroundLifecycle
import dev.motionfusion.app.platform.RenewedWakeLock
import dev.motionfusion.app.settings.RecordingLimits
import dev.motionfusion.app.ui.Formats
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.Continuation
import dev.motionfusion.core.session.RemoteStart

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
 *
 * The service is a shell: it owns the app's one foreground lifecycle ([ForegroundLifecycle]: foreground, wake lock,
 * notifications, leaving) and hands each start to the recording's lifecycle ([RecordingLifecycle]), which coordinates
 * the limits ([RecordingLimitWatch]), the notifications ([RecordingNotifications]) and the restart ([RecordingResumption]).
 */
class RecordingService : Service() {
    private lateinit var recording: RecordingLifecycle
    private lateinit var foreground: ForegroundLifecycle

    /** Notifications posted by the updates (for tests: a few a minute, not one a second). */
    internal val notificationUpdates: Int get() = recording.notificationUpdates

    override fun onCreate() {
        super.onCreate()
        val deps = (application as RecordingDependencies.Provider).recordingDependencies
        foreground = ForegroundLifecycle(this, NOTIFICATION_ID, FOREGROUND_SERVICE_TYPE, "MotionFusion:recording", deps.clock, deps::startForeground)
        recording = RecordingLifecycle(this, deps, foreground, RecordingNotifications(this, deps.clock))
    }

    override fun onBind(intent: Intent?): IBinder? = null

    override fun onStartCommand(intent: Intent?, flags: Int, startId: Int): Int {
        when (intent?.action) {
            ACTION_STOP -> recording.stopByUser()
            ACTION_START -> {
                // A new recording: an interrupted one is no longer offered (its session stays as it is, repaired by the start).
                foreground.cancel(INTERRUPTED_NOTIFICATION_ID)
                recording.start(still = intent.getBooleanExtra(EXTRA_STILL, false), remote = remoteStartOf(intent))
            }
            // Restarted by the system after the process died (START_STICKY): the recording resumes if one was running.
            null -> if (recording.idle) recording.resume()
            // The user tapped "tap to continue" (or Continue in the app): the interrupted recording goes on.
            ACTION_CONTINUE -> {
                foreground.cancel(INTERRUPTED_NOTIFICATION_ID)
                if (recording.idle) recording.resume()
            }
            else -> if (recording.idle) stopSelf()
        }
        return START_STICKY
    }

    override fun onDestroy() {
        // The system destroys a stopped service only after the recording ended; if it happens while recording (it
        // should not), what is queued is finished rather than left open.
        recording.destroy()
        super.onDestroy()
    }

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

        private fun startForeground(context: Context, intent: Intent): Foreground.Refusal? = ForegroundLifecycle.start(context, intent)

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
