// fusion-cli: the `fusion` command (fusion-cli/pom.xml; Maven builds target/fusion.jar for bin/fusion).
plugins {
    alias(libs.plugins.kotlin.jvm)
    application
}

kotlin {
    jvmToolchain(17)
}

sourceSets {
    main { kotlin.srcDirs("src/main/kotlin") }
    test { kotlin.srcDirs("src/test/kotlin") }
}

application {
    mainClass.set("dev.motionfusion.cli.MainKt")
}

dependencies {
    implementation(project(":fusion-core"))
    implementation(libs.kotlin.stdlib)
    testImplementation(platform(libs.junit.bom))
    testImplementation(libs.junit.jupiter)
}

tasks.test {
    useJUnitPlatform()
}
