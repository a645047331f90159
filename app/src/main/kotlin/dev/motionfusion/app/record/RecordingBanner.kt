package dev.motionfusion.app.record

import dev.motionfusion.app.ui.setTextIfChanged
import android.content.Context
import android.content.Intent
import android.text.format.DateUtils
import android.util.AttributeSet
import android.view.View
import android.widget.Button
import android.widget.LinearLayout
import android.widget.TextView
import androidx.core.view.ViewCompat
import androidx.core.view.accessibility.AccessibilityNodeInfoCompat
import androidx.lifecycle.Lifecycle
import androidx.lifecycle.findViewTreeLifecycleOwner
import androidx.lifecycle.lifecycleScope
import androidx.lifecycle.repeatOnLifecycle
import dev.motionfusion.app.R
import kotlinx.coroutines.Job
import kotlinx.coroutines.delay
import kotlinx.coroutines.flow.collectLatest
import kotlinx.coroutines.launch

/**
 * The recording, seen from every screen but the live one (whose record bar shows it): a slim
 * banner under the app bar, `res/layout/recording_banner.xml`, that each screen's layout
 * includes. While a recording runs or starts it shows the elapsed time and how many streams are
 * recorded ("Recording 02:13 · 4 streams"), refreshed every second; a tap goes back to the live
 * screen, Stop ends the recording (after a confirmation) as the record bar's Stop does. Otherwise it is gone. It reads
 * [Recordings.state] of the application's graph while its screen is started, and needs nothing
 * from the screen's code.
 */
class RecordingBanner(context: Context, attrs: AttributeSet?) : LinearLayout(context, attrs) {
    private val deps = (context.applicationContext as? RecordingDependencies.Provider)?.recordingDependencies
    private lateinit var text: TextView
    private var watching: Job? = null
    private val announcer = RecordingAnnouncer { announceForAccessibility(it) }

    /** Stop's confirmation on screen, for tests. */
    internal var dialog: androidx.appcompat.app.AlertDialog? = null
        private set

    override fun onFinishInflate() {
        super.onFinishInflate()
        text = findViewById(R.id.recording_banner_text)
        findViewById<Button>(R.id.recording_banner_stop).setOnClickListener { dialog = confirmStop(context) }
        setOnClickListener { openLiveScreen() }
        // Read as its text; the tap's action named for accessibility services.
        ViewCompat.replaceAccessibilityAction(this, AccessibilityNodeInfoCompat.AccessibilityActionCompat.ACTION_CLICK, context.getString(R.string.recording_banner_open), null)
        show(deps?.recordings?.state?.value ?: RecordingState.Idle)
    }

    override fun onAttachedToWindow() {
        super.onAttachedToWindow()
        val recordings = deps?.recordings ?: return
        val owner = findViewTreeLifecycleOwner() ?: return
        watching?.cancel()
        watching = owner.lifecycleScope.launch {
            owner.repeatOnLifecycle(Lifecycle.State.STARTED) {
                recordings.state.collectLatest { s ->
                    show(s)
                    // The elapsed time, until the state changes (which cancels this loop).
                    while (s is RecordingState.Active) {
                        delay(1_000)
                        show(s)
                    }
                }
            }
        }
    }

    override fun onDetachedFromWindow() {
        watching?.cancel()
        watching = null
        super.onDetachedFromWindow()
    }

    private fun show(s: RecordingState) {
        announcer.update(s) { RecordingAnnouncer.text(context, it) }
        val line = when (s) {
            is RecordingState.Active -> {
                val elapsed = DateUtils.formatElapsedTime(s.elapsedS(deps!!.clock.elapsedRealtimeNanos() / 1_000_000))
                val what = context.getString(if (s.still) R.string.recording_banner_still else R.string.recording_banner_active, elapsed)
                val line = if (s.streams == 0) what else context.getString(R.string.recording_banner_streams_line, what, resources.getQuantityString(R.plurals.recording_banner_streams, s.streams, s.streams))
                s.continues?.let { context.getString(R.string.recording_banner_streams_line, line, context.getString(R.string.record_resumed_short, RecordingService.gapText(it))) } ?: line
            }
            is RecordingState.Preparing -> s.line(context)
            else -> null
        }
        visibility = if (line == null) View.GONE else View.VISIBLE
        if (line != null) text.setTextIfChanged(line)
    }

    /** The live screen: the launcher activity, named by the manifest (record does not depend on the screens), brought back rather than started anew. */
    private fun openLiveScreen() {
        val intent = context.packageManager.getLaunchIntentForPackage(context.packageName) ?: return
        context.startActivity(intent.addFlags(Intent.FLAG_ACTIVITY_CLEAR_TOP or Intent.FLAG_ACTIVITY_SINGLE_TOP))
    }
}
