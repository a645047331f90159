package dev.motionfusion.app.calibration

import android.os.Bundle
import android.view.View
import android.view.WindowManager
import android.widget.Button
import android.widget.TextView
import androidx.appcompat.app.AppCompatActivity
import androidx.lifecycle.Lifecycle
import androidx.lifecycle.ViewModel
import androidx.lifecycle.ViewModelProvider
import androidx.lifecycle.lifecycleScope
import androidx.lifecycle.repeatOnLifecycle
import com.google.android.material.button.MaterialButtonToggleGroup
import com.google.android.material.materialswitch.MaterialSwitch
import com.google.android.material.progressindicator.LinearProgressIndicator
import dev.motionfusion.app.R
import dev.motionfusion.app.platform.AppVersion
import dev.motionfusion.app.record.RecordingService
import dev.motionfusion.app.record.RecordingState
import dev.motionfusion.app.ui.fitToSystemBars
import kotlinx.coroutines.delay
import kotlinx.coroutines.flow.combine
import kotlinx.coroutines.launch

/**
 * The guided calibration (docs/CALIBRATION.md, "In the app"): the magnetometer turn-through
 * with its coverage map, the accelerometer's six faces with the gyroscope bias from their still
 * periods, each result with its quality, stored per device in [CalibrationStore]; the switch
 * that applies it in the live filter; and the still recording for `fusion allan` (a recording
 * of the recording service, marked still). Readings come from the app's one capture.
 */
class CalibrationActivity : AppCompatActivity() {
    internal lateinit var viewModel: CalibrationViewModel
        private set
    private lateinit var deps: CalibrationDependencies
    private lateinit var store: CalibrationStore
    private lateinit var useLive: MaterialSwitch
    private lateinit var steps: MaterialButtonToggleGroup
    private lateinit var instruction: TextView
    private lateinit var map: CoverageMapView
    private lateinit var faces: PoseFacesView
    private lateinit var progress: LinearProgressIndicator
    private lateinit var progressText: TextView
    private lateinit var result: TextView
    private lateinit var primary: Button
    private lateinit var save: Button
    private lateinit var stored: TextView

    override fun onCreate(savedInstanceState: Bundle?) {
        super.onCreate(savedInstanceState)
        setContentView(R.layout.activity_calibration)
        fitToSystemBars(findViewById(R.id.calibration_root))
        setSupportActionBar(findViewById(R.id.toolbar))
        supportActionBar?.setDisplayHomeAsUpEnabled(true)
        deps = (application as CalibrationDependencies.Provider).calibrationDependencies
        store = deps.calibrationStore
        val made = "Motion Fusion ${AppVersion.of(this)} guided calibration"
        viewModel = ViewModelProvider(this, object : ViewModelProvider.Factory {
            @Suppress("UNCHECKED_CAST")
            override fun <T : ViewModel> create(modelClass: Class<T>): T =
                CalibrationViewModel(deps.calibrationSource, store, CalibrationDependencies.settings, deps.calibrationCompute, deps.io, made) as T
        })[CalibrationViewModel::class.java]
        steps = findViewById(R.id.step_group)
        instruction = findViewById(R.id.instruction)
        map = findViewById(R.id.coverage_map)
        faces = findViewById(R.id.pose_faces)
        progress = findViewById(R.id.progress)
        progressText = findViewById(R.id.progress_text)
        result = findViewById(R.id.result)
        primary = findViewById(R.id.primary_action)
        save = findViewById(R.id.save)
        stored = findViewById(R.id.stored)
        // Only a change of step resets it: the toggle restored after a rotation re-checks the current one.
        steps.addOnButtonCheckedListener { _, id, checked ->
            if (checked && stepOf(id) != viewModel.state.value.step) viewModel.select(stepOf(id))
        }
        primary.setOnClickListener { onPrimary() }
        save.setOnClickListener { viewModel.save() }
        useLive = findViewById(R.id.use_live)
        useLive.setOnCheckedChangeListener { _, on -> if (on != store.useInLiveFilter.value) store.setUseInLiveFilter(on) }
        lifecycleScope.launch {
            repeatOnLifecycle(Lifecycle.State.STARTED) {
                launch { viewModel.state.collect { render() } }
                launch { deps.recordings.state.collect { render() } }
                launch {
                    // The still recording's elapsed time.
                    while (true) {
                        delay(1_000)
                        if (viewModel.state.value.step == CalibrationStep.STILL) render()
                    }
                }
                launch {
                    combine(store.calibration, store.useInLiveFilter) { c, on -> c to on }.collect { (c, on) ->
                        if (useLive.isChecked != on) useLive.isChecked = on
                        stored.text = CalibrationText.stored(this@CalibrationActivity, c, on)
                    }
                }
            }
        }
    }

    private fun stepOf(buttonId: Int) = when (buttonId) {
        R.id.step_poses -> CalibrationStep.POSES
        R.id.step_still -> CalibrationStep.STILL
        else -> CalibrationStep.MAGNETOMETER
    }

    private fun onPrimary() {
        val s = viewModel.state.value
        when {
            s.step == CalibrationStep.STILL -> {
                val rec = deps.recordings.state.value
                if (rec is RecordingState.Active && rec.still) {
                    RecordingService.stop(this)
                } else {
                    RecordingService.start(this, still = true)?.let { reason -> deps.recordings.set(RecordingState.NotStarted(reason)) }
                }
            }
            s.stage == CalibrationStage.COLLECTING -> viewModel.finish()
            else -> viewModel.start()
        }
    }

    override fun onSupportNavigateUp(): Boolean {
        finish()
        return true
    }

    override fun onStart() {
        super.onStart()
        viewModel.resume()
    }

    override fun onStop() {
        // Sensors stay registered through a rotation, not while the screen is away; what was collected is kept either way.
        if (!isChangingConfigurations) viewModel.pause()
        super.onStop()
    }

    private fun render() {
        val s = viewModel.state.value
        val stepButton = when (s.step) {
            CalibrationStep.MAGNETOMETER -> R.id.step_magnetometer
            CalibrationStep.POSES -> R.id.step_poses
            CalibrationStep.STILL -> R.id.step_still
        }
        if (steps.checkedButtonId != stepButton) steps.check(stepButton)
        // The screen stays on while the phone is turned through or posed (the still recording is made with it off).
        if (s.stage == CalibrationStage.COLLECTING && s.step != CalibrationStep.STILL) {
            window.addFlags(WindowManager.LayoutParams.FLAG_KEEP_SCREEN_ON)
        } else {
            window.clearFlags(WindowManager.LayoutParams.FLAG_KEEP_SCREEN_ON)
        }
        val mag = s.step == CalibrationStep.MAGNETOMETER
        val still = s.step == CalibrationStep.STILL
        map.visibility = if (mag) View.VISIBLE else View.GONE
        faces.visibility = if (s.step == CalibrationStep.POSES) View.VISIBLE else View.GONE
        findViewById<View>(R.id.calibration_picture)?.visibility = if (still) View.GONE else View.VISIBLE
        save.visibility = if (still) View.GONE else View.VISIBLE
        if (still && s.unavailable == null) {
            renderStill()
            return
        }
        map.setCells(s.cellHits)
        faces.setFaces(s.facesHeld, s.askedFace)
        instruction.text = CalibrationText.instruction(this, s)
        val fraction = if (mag) s.coverage else s.facesHeld.size / 6.0
        progress.setProgressCompat((100 * fraction).toInt().coerceIn(0, 100), false)
        progressText.text = CalibrationText.progress(this, s)
        result.text = CalibrationText.result(this, s)
        primary.isEnabled = s.unavailable == null
        primary.text = getString(when (s.stage) {
            CalibrationStage.READY -> R.string.calibration_start
            CalibrationStage.COLLECTING -> R.string.calibration_finish
            CalibrationStage.RESULT -> R.string.calibration_again
        })
        save.isEnabled = s.stage == CalibrationStage.RESULT && s.hasAccepted && !s.saved
        save.text = getString(if (s.saved) R.string.calibration_saved else R.string.calibration_save)
    }

    private fun renderStill() {
        val t = CalibrationText.still(this, deps.recordings.state.value, deps.clock.elapsedRealtimeNanos() / 1_000_000)
        instruction.text = t.instruction
        progress.setProgressCompat((100 * t.fractionOfHour).toInt().coerceIn(0, 100), false)
        progressText.text = t.progress
        result.text = t.result
        primary.isEnabled = !t.busy
        primary.text = getString(if (t.recording) R.string.calibration_still_stop else R.string.calibration_still_start)
    }
}
