package dev.motionfusion.app

import android.content.Intent
import android.hardware.display.DisplayManager
import android.os.Bundle
import android.os.Handler
import android.os.Looper
import android.view.Choreographer
import android.view.Menu
import android.view.MenuItem
import android.view.Surface
import androidx.appcompat.app.AppCompatActivity
import androidx.lifecycle.Lifecycle
import androidx.lifecycle.lifecycleScope
import androidx.lifecycle.repeatOnLifecycle
import androidx.activity.viewModels
import dev.motionfusion.app.calibration.CalibrationActivity
import dev.motionfusion.app.stream.StreamActivity
import dev.motionfusion.app.fusion.FusionState
import dev.motionfusion.app.live.LiveViewModel
import dev.motionfusion.app.live.LiveScreen
import dev.motionfusion.app.settings.SettingsActivity
import dev.motionfusion.app.record.RecordBar
import dev.motionfusion.app.record.RecordingState
import dev.motionfusion.app.ui.PlotMarker
import dev.motionfusion.app.ui.fitToSystemBars
import kotlinx.coroutines.launch

/**
 * The live screen (layout, layout-land, layout-sw600dp: a turn recreates the activity with the
 * layout for its new shape; the capture and its filter carry on). The fusion runs in the
 * application's capture (off the main thread, and surviving configuration changes), reached
 * through [LiveViewModel]; the app bar's actions are res/menu/live.xml. This activity keeps it
 * running while visible (onStart..onStop, and through a configuration change's recreation), collects its state while started (repeatOnLifecycle) and draws the latest
 * state at most once per display frame: each new state or display change asks for the next
 * frame, and the frame draws whatever is newest then.
 */
class MainActivity : AppCompatActivity() {
    private val model: LiveViewModel by viewModels { LiveViewModel.Factory((application as MotionFusionApp).graph.capture) }
    private val recordings by lazy { (application as MotionFusionApp).graph.recordings }
    private lateinit var screen: LiveScreen
    private var shown: FusionState? = null
    private var shownRotation = -1
    private var framePending = false

    private val frame = Choreographer.FrameCallback {
        framePending = false
        render()
    }

    private val displays = object : DisplayManager.DisplayListener {
        override fun onDisplayAdded(displayId: Int) = Unit
        override fun onDisplayRemoved(displayId: Int) = Unit
        override fun onDisplayChanged(displayId: Int) = requestFrame() // e.g. a 180° turn, which is no configuration change
    }

    override fun onCreate(savedInstanceState: Bundle?) {
        super.onCreate(savedInstanceState)
        setContentView(R.layout.activity_main)
        fitToSystemBars(findViewById(R.id.live_root))
        setSupportActionBar(findViewById(R.id.toolbar))
        screen = LiveScreen(this, model.sensorInfo, model.plotTrace)
        RecordBar.attach(this, findViewById(R.id.record_bar))
        lifecycleScope.launch { repeatOnLifecycle(Lifecycle.State.STARTED) { recordings.state.collect { requestFrame() } } }
        lifecycleScope.launch {
            repeatOnLifecycle(Lifecycle.State.STARTED) { model.state.collect { requestFrame() } }
        }
        render()
    }

    override fun onCreateOptionsMenu(menu: Menu): Boolean {
        menuInflater.inflate(R.menu.live, menu)
        return true
    }

    override fun onOptionsItemSelected(item: MenuItem): Boolean = when (item.itemId) {
        R.id.action_settings -> {
            startActivity(Intent(this, SettingsActivity::class.java))
            true
        }
        R.id.open_calibration -> {
            startActivity(Intent(this, CalibrationActivity::class.java))
            true
        }
        R.id.open_stream -> {
            startActivity(Intent(this, StreamActivity::class.java))
            true
        }
        else -> super.onOptionsItemSelected(item)
    }

    override fun onStart() {
        super.onStart()
        model.onVisible()
        getSystemService(DisplayManager::class.java).registerDisplayListener(displays, Handler(Looper.getMainLooper()))
    }

    override fun onStop() {
        getSystemService(DisplayManager::class.java).unregisterDisplayListener(displays)
        Choreographer.getInstance().removeFrameCallback(frame)
        framePending = false
        // A rotation, a theme, font-size or window-size change recreates the activity at once: the capture (the
        // application's, held by the ViewModel, which survives it) stays registered, with no gap in the filter, the
        // plot or a recording's batching; it is let go only when the screen really goes away.
        if (!isChangingConfigurations) model.onHidden()
        super.onStop()
    }

    private fun requestFrame() {
        if (framePending) return
        framePending = true
        Choreographer.getInstance().postFrameCallback(frame)
    }

    /** Draws the latest state when it or the display rotation changed since the last frame. */
    private fun render() {
        val s = model.state.value
        val rotation = displayRotation()
        if (s === shown && rotation == shownRotation) return
        shown = s
        shownRotation = rotation
        screen.show(s, rotation, recordingMarkers())
    }

    /** The markers of the running recording, for the live plot. */
    private fun recordingMarkers(): List<PlotMarker> {
        val active = recordings.state.value as? RecordingState.Active ?: return emptyList()
        return active.markers().map { PlotMarker(it.timestampNs, it.label) }
    }

    private fun displayRotation(): Int {
        // An activity's WindowManager belongs to the activity's display (Activity.getDisplay, API 30,
        // is the same display but throws before the window is attached).
        @Suppress("DEPRECATION")
        return windowManager.defaultDisplay?.rotation ?: Surface.ROTATION_0
    }
}
