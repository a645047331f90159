package dev.motionfusion.app.calibration

import android.content.pm.PackageManager
import android.os.Bundle
import android.view.View
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
import dev.motionfusion.app.ui.fitToSystemBars
import kotlinx.coroutines.launch

/**
 * The guided calibration (docs/CALIBRATION.md, "In the app"): the magnetometer turn-through
 * with its coverage map, the accelerometer's six faces with the gyroscope bias from their still
 * periods, each result with its quality, stored per device in [CalibrationStore].
 */
class CalibrationActivity : AppCompatActivity() {
    internal lateinit var viewModel: CalibrationViewModel
        private set
    private lateinit var store: CalibrationStore
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
        supportActionBar?.setDisplayHomeAsUpEnabled(true)
        store = CalibrationStores.get(this)
        val made = "Motion Fusion ${appVersion()} guided calibration"
        viewModel = ViewModelProvider(this, object : ViewModelProvider.Factory {
            @Suppress("UNCHECKED_CAST")
            override fun <T : ViewModel> create(modelClass: Class<T>): T =
                CalibrationViewModel(CalibrationDeps.source(applicationContext), store, CalibrationDeps.settings, CalibrationDeps.compute, CalibrationDeps.io, made) as T
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
        steps.addOnButtonCheckedListener { _, id, checked ->
            if (checked) viewModel.select(if (id == R.id.step_poses) CalibrationStep.POSES else CalibrationStep.MAGNETOMETER)
        }
        primary.setOnClickListener {
            if (viewModel.state.value.stage == CalibrationStage.COLLECTING) viewModel.finish() else viewModel.start()
        }
        save.setOnClickListener { viewModel.save() }
        findViewById<MaterialSwitch>(R.id.use_live).apply {
            isChecked = store.useInLiveFilter
            setOnCheckedChangeListener { _, on -> store.useInLiveFilter = on }
        }
        lifecycleScope.launch {
            repeatOnLifecycle(Lifecycle.State.STARTED) {
                launch { viewModel.state.collect { render(it) } }
                launch { store.calibration.collect { stored.text = CalibrationText.stored(this@CalibrationActivity, it) } }
            }
        }
    }

    override fun onSupportNavigateUp(): Boolean {
        finish()
        return true
    }

    override fun onStop() {
        // Sensors stay registered through a rotation, not while the screen is away.
        if (!isChangingConfigurations && viewModel.state.value.stage == CalibrationStage.COLLECTING) viewModel.select(viewModel.state.value.step)
        super.onStop()
    }

    private fun render(s: CalibrationUiState) {
        val stepButton = if (s.step == CalibrationStep.POSES) R.id.step_poses else R.id.step_magnetometer
        if (steps.checkedButtonId != stepButton) steps.check(stepButton)
        val mag = s.step == CalibrationStep.MAGNETOMETER
        map.visibility = if (mag) View.VISIBLE else View.GONE
        faces.visibility = if (mag) View.GONE else View.VISIBLE
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

    private fun appVersion(): String = try {
        packageManager.getPackageInfo(packageName, 0).versionName ?: ""
    } catch (e: PackageManager.NameNotFoundException) {
        ""
    }
}
