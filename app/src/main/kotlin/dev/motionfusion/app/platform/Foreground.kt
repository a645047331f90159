package dev.motionfusion.app.platform

import android.app.Notification
import android.app.NotificationChannel
import android.app.NotificationManager
import android.app.Service
import android.content.Context
import android.os.Build
import android.os.PowerManager
import dev.motionfusion.app.R

/**
 * What the app's foreground services share (the recording's, docs/RECORDING.md, and the live stream's,
 * docs/STREAMING.md): their notification channels, entering the foreground with the manifest's type,
 * and a partial wake lock that times out unless renewed.
 */
object Foreground {
    /** The ongoing notification of a recording (quiet). */
    const val CHANNEL_RECORDING = "recording"

    /** A recording that ended by itself or could not start (heads-up). */
    const val CHANNEL_ALERTS = "recording-alerts"

    /** The ongoing notification of the live stream (quiet). */
    const val CHANNEL_STREAMING = "streaming"

    /** Creates the app's notification channels (API 26+, the app's minSdk; creating one again only renames it). */
    fun createChannels(context: Context) {
        val nm = context.getSystemService(NotificationManager::class.java)
        nm.createNotificationChannel(NotificationChannel(CHANNEL_RECORDING, context.getString(R.string.record_channel), NotificationManager.IMPORTANCE_LOW))
        nm.createNotificationChannel(NotificationChannel(CHANNEL_ALERTS, context.getString(R.string.record_alert_channel), NotificationManager.IMPORTANCE_HIGH))
        nm.createNotificationChannel(NotificationChannel(CHANNEL_STREAMING, context.getString(R.string.stream_channel), NotificationManager.IMPORTANCE_LOW))
    }

    /**
     * Enters the foreground through [starter] (ServiceCompat.startForeground, or a test's), with [type] on
     * Android 14+ (the type the manifest declares; earlier versions start without one). Returns why the
     * system refused, or null: Android 12+ refuses a start from the background
     * (ForegroundServiceStartNotAllowedException, an IllegalStateException), Android 14+ one whose type's
     * permission is missing (SecurityException).
     */
    fun enter(
        service: Service,
        id: Int,
        notification: Notification,
        type: Int,
        starter: (Service, Int, Notification, Int) -> Unit,
    ): String? = try {
        starter(service, id, notification, if (Build.VERSION.SDK_INT >= 34) type else 0)
        null
    } catch (e: IllegalStateException) {
        e.message ?: e.javaClass.simpleName
    } catch (e: SecurityException) {
        e.message ?: e.javaClass.simpleName
    }
}

/**
 * A partial wake lock named [tag] (non-wake-up sensors deliver with the screen off only under one)
 * that times out after [TIMEOUT_MS] unless [renewIfDue] renews it, so a crashed service cannot keep
 * the phone awake. Main thread.
 */
class RenewedWakeLock(private val context: Context, private val tag: String, private val clock: Clock) {
    private var lock: PowerManager.WakeLock? = null
    private var renewedNs = 0L

    val isHeld: Boolean get() = lock?.isHeld == true

    /** Takes the lock (again, with a fresh timeout, when held). */
    fun hold() {
        val l = lock ?: context.getSystemService(PowerManager::class.java)
            .newWakeLock(PowerManager.PARTIAL_WAKE_LOCK, tag)
            .apply { setReferenceCounted(false) }
            .also { lock = it }
        l.acquire(TIMEOUT_MS)
        renewedNs = clock.elapsedRealtimeNanos()
    }

    /** Renews the timeout once [RENEW_NS] have passed since the last renewal; nothing when not held. */
    fun renewIfDue() {
        if (lock == null) return
        if (clock.elapsedRealtimeNanos() - renewedNs >= RENEW_NS) hold()
    }

    fun release() {
        lock?.let { if (it.isHeld) it.release() }
        lock = null
    }

    companion object {
        /** The lock times out after 10 minutes unless renewed, every minute while held. */
        const val TIMEOUT_MS = 10 * 60 * 1000L
        const val RENEW_NS = 60_000_000_000L
    }
}
