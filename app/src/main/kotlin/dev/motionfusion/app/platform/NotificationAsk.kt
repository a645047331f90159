package dev.motionfusion.app.platform

import android.Manifest
import android.content.ActivityNotFoundException
import android.content.Intent
import android.content.pm.PackageManager
import android.os.Build
import android.provider.Settings
import androidx.activity.ComponentActivity
import androidx.activity.result.contract.ActivityResultContracts
import androidx.annotation.StringRes
import androidx.appcompat.app.AlertDialog
import androidx.core.content.ContextCompat
import com.google.android.material.dialog.MaterialAlertDialogBuilder
import dev.motionfusion.app.R

/**
 * The notification permission (Android 13+) that the app's foreground services' notifications
 * need — the recording's and the stream's, each with its Stop — asked before the first one starts:
 * an explanation ([title], [text]), then the system's question, or on without it ([skip]). Asked
 * once for the app ([answered], kept in the settings); [proceed] runs after the answer, whatever
 * it is, or at once when nothing is to be asked. After "without", [openSettings] is the way back:
 * the app's notification settings. Made while the activity is created (the Activity Result API
 * requires it).
 */
internal class NotificationAsk(
    private val activity: ComponentActivity,
    @StringRes private val title: Int,
    @StringRes private val text: Int,
    @StringRes private val skip: Int,
    /** Whether the question was answered before (kept in the settings), and remembering that it was. */
    private val answered: () -> Boolean,
    private val markAnswered: () -> Unit,
    private val proceed: () -> Unit,
) {
    /** The explanation on screen, for tests. */
    var dialog: AlertDialog? = null
        private set

    private val permission = activity.registerForActivityResult(ActivityResultContracts.RequestPermission()) {
        markAnswered()
        proceed()
    }

    /** True when notifications may be shown (always before Android 13). */
    val allowed: Boolean
        get() = Build.VERSION.SDK_INT < 33 ||
            ContextCompat.checkSelfPermission(activity, Manifest.permission.POST_NOTIFICATIONS) == PackageManager.PERMISSION_GRANTED

    /** True when the user went on without notifications: offer [openSettings]. */
    val declined: Boolean get() = !allowed && answered()

    /** [proceed] at once, or after the explanation and the system's question the first time on Android 13+. */
    fun thenProceed() {
        if (allowed || answered()) {
            proceed()
            return
        }
        dialog = MaterialAlertDialogBuilder(activity)
            .setTitle(title)
            .setMessage(text)
            .setCancelable(false)
            .setPositiveButton(R.string.record_notifications_continue) { _, _ -> permission.launch(Manifest.permission.POST_NOTIFICATIONS) }
            .setNegativeButton(skip) { _, _ ->
                markAnswered()
                proceed()
            }
            .show()
    }

    /** The app's notification settings, where the user turns them on after going on without. */
    fun openSettings() {
        try {
            activity.startActivity(Intent(Settings.ACTION_APP_NOTIFICATION_SETTINGS).putExtra(Settings.EXTRA_APP_PACKAGE, activity.packageName))
        } catch (_: ActivityNotFoundException) {
            activity.startActivity(Intent(Settings.ACTION_APPLICATION_DETAILS_SETTINGS, android.net.Uri.fromParts("package", activity.packageName, null)))
        }
    }
}
