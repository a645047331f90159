package dev.motionfusion.app.record

import dev.motionfusion.core.session.SessionStream
import android.app.Notification
import android.app.NotificationChannel
import android.app.NotificationManager
import android.app.PendingIntent
import android.app.Service
import android.content.Context
import android.content.Intent
import android.content.pm.ServiceInfo
import android.hardware.SensorManager
import android.os.Build
import android.os.Handler
import android.os.IBinder
import android.os.Looper
import android.os.PowerManager
import android.os.SystemClock
import android.text.format.DateUtils
import androidx.core.app.NotificationCompat
import androidx.core.app.ServiceCompat
import androidx.core.content.ContextCompat
import dev.motionfusion.app.MainActivity
import dev.motionfusion.app.R
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.filter.MadgwickFilter
import java.io.File

/**
 * Records every sensor stream into a session while the user wants it: a foreground service of
 * type `health`, started from the Record button, holding a partial wake lock (non-wake-up
 * sensors deliver with the screen off only under one) and an ongoing notification with the
 * elapsed time, the number of samples and a Stop action. It does not depend on any activity:
 * closing the app's screens does not stop it; only Stop (button or notification) or a storage
 * problem does, and a storage problem is told to the user.
 */
class RecordingService : Service() {
    private val main = Handler(Looper.getMainLooper())
    private var capture: SensorCapture? = null
    private var recorder: Recorder? = null
    private var session: File? = null
    private var wakeLock: PowerManager.WakeLock? = null
    private var startedElapsedMs = 0L
    private var startedWallMs = 0L

    private val tick = object : Runnable {
        override fun run() {
            if (recorder == null) return
            notificationManager().notify(NOTIFICATION_ID, ongoingNotification())
            main.postDelayed(this, 1_000)
        }
    }

    override fun onBind(intent: Intent?): IBinder? = null

    override fun onStartCommand(intent: Intent?, flags: Int, startId: Int): Int {
        when (intent?.action) {
            ACTION_STOP -> stopRecording()
            ACTION_START -> startRecording()
            // Restarted by the system after the process died: the interrupted session is
            // repaired by recovery; a new recording needs the user's action.
            else -> if (recorder == null) stopSelf()
        }
        return START_NOT_STICKY
    }

    private fun startRecording() {
        if (recorder != null) return
        createChannels()
        startedWallMs = System.currentTimeMillis()
        startedElapsedMs = SystemClock.elapsedRealtime()
        // Foreground first: startForegroundService() must be answered within a few seconds.
        goForeground()?.let { reason ->
            RecordingStatus.state = RecordingStatus.State.NotStarted(reason)
            notificationManager().notify(END_NOTIFICATION_ID, alertNotification(getString(R.string.record_not_started, reason)))
            stopSelf()
            return
        }

        val format = RecordingDeps.format
        InterruptedSessions.recoverAll(this, format)
        val dir = SessionFolders.newSession(this, startedWallMs)
        val ring = EventRing(RecordingDeps.ringCapacity)
        val sensorManager = getSystemService(SensorManager::class.java)
        val capture = SensorCapture(sensorManager, ring)
        val settings = FilterSettings()
        val metadata = RecordingMetadata.create(
            appVersion(),
            capture.sensors.map { (stream, s) -> RecordingMetadata.sensorInfo(stream, s, capture.requestedPeriodUs, 0) },
            settings,
            RecordingMetadata.anchorNow(),
        )
        val sink = try {
            dir.mkdirs()
            format.create(dir, metadata)
        } catch (e: Exception) {
            ended(dir, RecorderResult(RecordingEnd.WriteFailed(e.message ?: e.javaClass.simpleName), LongArray(SessionStream.entries.size), 0, 0))
            return
        }
        val minFree = RecordingDeps.minFreeBytes
        val recorder = Recorder(
            ring, sink, MadgwickFilter(settings),
            onEnd = { result -> onWriterEnded(dir, result) },
            freeBytes = { dir.usableSpace },
            minFreeBytes = minFree,
            anchorNow = RecordingMetadata::anchorNow,
        )
        this.capture = capture
        this.recorder = recorder
        this.session = dir
        RecordingStatus.state = RecordingStatus.State.Active(dir, startedElapsedMs) { recorder.rowCount }
        wakeLock = getSystemService(PowerManager::class.java)
            .newWakeLock(PowerManager.PARTIAL_WAKE_LOCK, "MotionFusion:recording")
            .apply { setReferenceCounted(false); acquire() }
        recorder.start()
        capture.start()
        main.post(tick)
    }

    /**
     * Enters the foreground, as a `health` service on Android 14+ (the type the manifest declares;
     * earlier versions do not know it). Returns why the system refused, or null: Android 12+ refuses
     * a start from the background (ForegroundServiceStartNotAllowedException, an
     * IllegalStateException), Android 14+ one whose type's permission is missing (SecurityException).
     */
    private fun goForeground(): String? = try {
        val type = if (Build.VERSION.SDK_INT >= 34) FOREGROUND_SERVICE_TYPE else 0
        RecordingDeps.startForeground(this, NOTIFICATION_ID, ongoingNotification(), type)
        null
    } catch (e: IllegalStateException) {
        e.message ?: e.javaClass.simpleName
    } catch (e: SecurityException) {
        e.message ?: e.javaClass.simpleName
    }

    /** Stop button or notification action: sensors first, then the writer drains and finishes. */
    private fun stopRecording() {
        val r = recorder
        if (r == null) {
            stopSelf()
            return
        }
        capture?.stop()
        capture = null
        r.stop()
    }

    /** Writer thread: the recording is over (stopped or failed). Repairs a failed session, then hands over to main. */
    private fun onWriterEnded(dir: File, result: RecorderResult) {
        if (result.end is RecordingEnd.WriteFailed) {
            try {
                val format = RecordingDeps.format
                if (format.isInterrupted(dir)) format.recover(dir)
            } catch (_: Exception) {
                // Still interrupted: the next start's recovery tries again.
            }
        }
        main.post { ended(dir, result) }
    }

    private fun ended(dir: File, result: RecorderResult) {
        capture?.stop()
        capture = null
        recorder = null
        session = null
        main.removeCallbacks(tick)
        wakeLock?.let { if (it.isHeld) it.release() }
        wakeLock = null
        RecordingStatus.state = RecordingStatus.State.Ended(dir, result)
        ServiceCompat.stopForeground(this, ServiceCompat.STOP_FOREGROUND_REMOVE)
        if (result.end.isFailure) notificationManager().notify(END_NOTIFICATION_ID, alertNotification(endMessage(this, result)))
        stopSelf()
    }

    override fun onDestroy() {
        // The system destroys a stopped service only after ended(); if it happens while
        // recording (it should not), finish what is queued rather than leave it open.
        if (recorder != null) stopRecording()
        main.removeCallbacks(tick)
        super.onDestroy()
    }

    private fun notificationManager() = getSystemService(NotificationManager::class.java)

    private fun createChannels() {
        val nm = notificationManager()
        nm.createNotificationChannel(
            NotificationChannel(CHANNEL_RECORDING, getString(R.string.record_channel), NotificationManager.IMPORTANCE_LOW),
        )
        nm.createNotificationChannel(
            NotificationChannel(CHANNEL_ALERTS, getString(R.string.record_alert_channel), NotificationManager.IMPORTANCE_HIGH),
        )
    }

    private fun ongoingNotification(): Notification {
        val elapsedS = if (startedElapsedMs == 0L) 0 else (SystemClock.elapsedRealtime() - startedElapsedMs) / 1000
        val rows = recorder?.rowCount ?: 0L
        val stop = PendingIntent.getService(
            this, 1, Intent(this, RecordingService::class.java).setAction(ACTION_STOP),
            PendingIntent.FLAG_IMMUTABLE or PendingIntent.FLAG_UPDATE_CURRENT,
        )
        return NotificationCompat.Builder(this, CHANNEL_RECORDING)
            .setSmallIcon(R.drawable.ic_record)
            .setContentTitle(getString(R.string.record_notification_title))
            .setContentText(getString(R.string.record_notification_text, DateUtils.formatElapsedTime(elapsedS), rows))
            .setOngoing(true)
            .setOnlyAlertOnce(true)
            .setShowWhen(true)
            .setWhen(startedWallMs)
            .setUsesChronometer(true)
            .setCategory(NotificationCompat.CATEGORY_SERVICE)
            .setForegroundServiceBehavior(NotificationCompat.FOREGROUND_SERVICE_IMMEDIATE)
            .setContentIntent(openApp())
            .addAction(0, getString(R.string.record_stop), stop)
            .build()
    }

    private fun alertNotification(text: String): Notification =
        NotificationCompat.Builder(this, CHANNEL_ALERTS)
            .setSmallIcon(R.drawable.ic_record)
            .setContentTitle(getString(R.string.record_failed_title))
            .setContentText(text)
            .setStyle(NotificationCompat.BigTextStyle().bigText(text))
            .setAutoCancel(true)
            .setContentIntent(openApp())
            .build()

    private fun openApp(): PendingIntent = PendingIntent.getActivity(
        this, 0, Intent(this, MainActivity::class.java).addFlags(Intent.FLAG_ACTIVITY_SINGLE_TOP),
        PendingIntent.FLAG_IMMUTABLE,
    )

    private fun appVersion(): String =
        try {
            packageManager.getPackageInfo(packageName, 0).versionName ?: ""
        } catch (_: Exception) {
            ""
        }

    companion object {
        internal const val ACTION_START = "dev.motionfusion.app.record.START"
        internal const val ACTION_STOP = "dev.motionfusion.app.record.STOP"
        internal const val NOTIFICATION_ID = 7001
        internal const val END_NOTIFICATION_ID = 7002
        internal const val CHANNEL_RECORDING = "recording"
        internal const val CHANNEL_ALERTS = "recording-alerts"

        /** The manifest's android:foregroundServiceType; its permission is FOREGROUND_SERVICE_HEALTH (ForegroundServiceTest). */
        internal const val FOREGROUND_SERVICE_TYPE = ServiceInfo.FOREGROUND_SERVICE_TYPE_HEALTH

        /**
         * Starts a recording; call from a user action (Android 12+ forbids it from the background).
         * Returns why the system refused to start the service, or null.
         */
        fun start(context: Context): String? = try {
            ContextCompat.startForegroundService(context, Intent(context, RecordingService::class.java).setAction(ACTION_START))
            null
        } catch (e: IllegalStateException) {
            e.message ?: e.javaClass.simpleName
        }

        fun stop(context: Context) {
            context.startService(Intent(context, RecordingService::class.java).setAction(ACTION_STOP))
        }

        /** What to tell the user about how a recording ended. */
        internal fun endMessage(context: Context, result: RecorderResult): String {
            val rows = result.rows
            return when (val e = result.end) {
                RecordingEnd.Stopped -> context.getString(R.string.record_end_stopped, rows)
                is RecordingEnd.QueueOverflow -> context.getString(R.string.record_end_overflow, rows)
                is RecordingEnd.StorageLow -> context.getString(R.string.record_end_storage_low, rows, e.freeBytes / (1024 * 1024))
                is RecordingEnd.WriteFailed -> context.getString(R.string.record_end_write_failed, e.message, rows)
            }
        }
    }
}
