package dev.motionfusion.app.platform

import android.app.Notification
import android.app.NotificationChannel
import android.app.NotificationManager
import android.app.Service
import android.content.Context
import android.os.Build
import android.os.PowerManager
import android.util.Log
import androidx.annotation.StringRes
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
     * system refused ([Refusal]; the exception goes to the log, never to the screen), or null.
     */
    fun enter(
        service: Service,
        id: Int,
        notification: Notification,
        type: Int,
        starter: (Service, Int, Notification, Int) -> Unit,
    ): Refusal? = try {
        starter(service, id, notification, if (Build.VERSION.SDK_INT >= 34) type else 0)
        null
    } catch (e: IllegalStateException) {
        Refusal.of(e, service.javaClass.simpleName)
    } catch (e: SecurityException) {
        Refusal.of(e, service.javaClass.simpleName)
    }

    /**
     * Why the system refused a foreground service, each with the words the user reads ([text], a string
     * resource in every language the app ships); the framework's message goes to the log only.
     */
    enum class Refusal(@StringRes val text: Int) {
        /**
         * Android 12+: the start came while the app was in the background and is not exempt
         * (ForegroundServiceStartNotAllowedException, an IllegalStateException; also Android 8+'s
         * IllegalStateException for a service started from the background).
         */
        BACKGROUND(R.string.foreground_refused_background),

        /** Android 14+: the permission of the service's type is missing (SecurityException). */
        PERMISSION(R.string.foreground_refused_permission),
        ;

        companion object {
            /** The kind of [e] (thrown by a start of [what]); logged with its message. */
            fun of(e: RuntimeException, what: String): Refusal {
                val kind = if (e is SecurityException) PERMISSION else BACKGROUND
                Log.w("Foreground", "$what: the system refused the foreground ($kind)", e)
                return kind
            }
        }
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
